"""The API reference, from the docstrings: every public module of a package, found at build time.

``.. tegraph-api:: tegraph.analysis`` documents each public module of the package
(no part of its dotted name starts with ``_``) and, in each, the names it defines
or takes from a private module (``maxplus.dense.star`` from ``maxplus._closure``):
every object is described once, and a name that a public module re-exports from
another public one (``tegraph.analyze`` for ``tegraph.api.analyze``) is resolved
to that description (``missing-reference`` below). A new module is in the
reference as soon as it exists; a public function, class, method or property
without a docstring fails the build under ``-W``.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import pkgutil
import types
from pathlib import Path
from typing import Any

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.application import Sphinx
from sphinx.errors import PycodeError
from sphinx.pycode import ModuleAnalyzer
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

logger = logging.getLogger(__name__)

PACKAGES = ("maxplus", "tegraph")


def public_modules(package: str, recursive: bool = True) -> list[str]:
    """The package and its public modules, in the order of a depth-first walk."""
    found = [package]
    path = getattr(importlib.import_module(package), "__path__", None)
    if path is None:
        return found
    for info in sorted(pkgutil.iter_modules(path), key=lambda i: (i.ispkg, i.name)):
        if info.name.startswith("_"):
            continue
        name = f"{package}.{info.name}"
        found += public_modules(name) if recursive and info.ispkg else [name]
    return found


def _private(module: str) -> bool:
    return any(part.startswith("_") for part in module.split("."))


def _homes(module: types.ModuleType) -> dict[str, str]:
    """Name -> the module the source of ``module`` takes it from (itself when it assigns it)."""
    source = Path(module.__file__ or "")
    if source.suffix != ".py":
        return {}
    tree = ast.parse(source.read_text(encoding="utf-8"))
    name = module.__name__
    package = name if source.name == "__init__.py" else name.rpartition(".")[0]
    homes: dict[str, str] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = package
            for _ in range(max(node.level - 1, 0)):
                base = base.rpartition(".")[0]
            origin = (f"{base}.{node.module}" if node.module else base) if node.level else (
                node.module or "")
            for alias in node.names:
                homes.setdefault(alias.asname or alias.name, origin)
        elif isinstance(node, ast.Assign) and node in tree.body:
            for target in node.targets:
                if isinstance(target, ast.Name):
                    homes.setdefault(target.id, module.__name__)
                    if target.id == "_WHERE" and isinstance(node.value, ast.Dict):
                        for k, v in zip(node.value.keys, node.value.values):
                            if isinstance(k, ast.Constant) and isinstance(v, ast.Constant):
                                homes[k.value] = v.value
        elif isinstance(node, ast.AnnAssign) and node in tree.body and isinstance(
                node.target, ast.Name):
            homes.setdefault(node.target.id, module.__name__)
    return homes


def members_of(name: str) -> list[str]:
    """The names :func:`public_modules`' module ``name`` is the place to describe."""
    module = importlib.import_module(name)
    homes = _homes(module)
    listed = list(getattr(module, "__all__", ()))
    names = listed + [n for n in vars(module) if not n.startswith("_") and n not in listed]
    try:
        documented = {attr for (ns, attr) in ModuleAnalyzer.for_module(name).find_attr_docs()
                      if ns == ""}
    except PycodeError:  # a compiled module: no source to read attribute docstrings from
        documented = set()
    out = []
    for n in names:
        obj = getattr(module, n, None)
        if obj is None or inspect.ismodule(obj):
            continue
        if not (inspect.isclass(obj) or inspect.isroutine(obj)) and n not in documented:
            continue  # a constant is described where its docstring is
        home = homes.get(n) or getattr(obj, "__module__", None) or ""
        if home == name or (n in listed and home.startswith(PACKAGES) and _private(home)):
            out.append(n)
    return out


class TegraphApi(SphinxDirective):
    """``.. tegraph-api:: PACKAGE``: a section per public module, its own members."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        lines: list[str] = []
        for name in public_modules(self.arguments[0]):
            title = f"``{name}``"
            members = members_of(name)
            lines += [title, "-" * len(title), "", f".. automodule:: {name}"]
            if members:  # an empty ``:members:`` would mean every member
                lines += [f"   :members: {', '.join(members)}", "   :undoc-members:"]
            lines.append("")
        container = nodes.section()
        nested_parse_with_titles(self.state, StringList(lines, source=self.arguments[0]),
                                 container)
        return container.children


_DESCRIBED: dict[int, str] = {}
"""``id`` of every object the reference describes at module level -> its name there."""


def _note_described(app: Sphinx) -> None:
    _DESCRIBED.clear()
    for package in PACKAGES:
        for name in public_modules(package):
            module = importlib.import_module(name)
            for member in members_of(name):
                _DESCRIBED.setdefault(id(getattr(module, member)), f"{name}.{member}")


def _described_name(dotted: str) -> str | None:
    """The name under which the reference describes what ``dotted`` names, or None."""
    parts = dotted.split(".")
    if not all(parts):  # a relative target (".name"): the domain's own search handles it
        return None
    for cut in range(len(parts) - 1, 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:cut]))
        except (ImportError, ValueError):
            continue
        best = None
        for i, attr in enumerate(parts[cut:]):
            obj = inspect.getattr_static(obj, attr, None) if inspect.isclass(obj) else getattr(
                obj, attr, None)
            if obj is None:
                return None
            if id(obj) in _DESCRIBED:
                best = ".".join([_DESCRIBED[id(obj)], *parts[cut + i + 1:]])
        return best
    return None


def _resolve_alias(app: Sphinx, env: Any, node: Any, contnode: Any) -> Any:
    """A reference to a re-exported name resolves to the object's one description."""
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"]
    candidates = [target]
    if node.get("py:class") and node.get("py:module"):
        candidates.append(f"{node['py:module']}.{node['py:class']}.{target}")
    if node.get("py:module"):
        candidates.append(f"{node['py:module']}.{target}")
    for dotted in candidates:
        described = _described_name(dotted)
        if described and described != dotted:
            new = node.deepcopy()
            new["py:module"] = new["py:class"] = None
            found = env.get_domain("py").resolve_xref(
                env, node["refdoc"], app.builder, node["reftype"], described, new, contnode)
            if found is not None:
                return found
    return None


def _undocumented(app: Sphinx, what: str, name: str, obj: Any, skip: bool,
                  options: Any) -> bool | None:
    """A public function, class, method or property of tegraph or maxplus without a
    docstring is a warning (an error under ``-W``): the reference would list it with
    nothing to say. Fields and constants are listed with their type or value (a
    dataclass's fields are described in its docstring); type aliases are left out."""
    if isinstance(obj, (types.GenericAlias, types.UnionType)):
        return True
    if skip or name.startswith("_"):
        return None
    target = obj.fget if isinstance(obj, property) else obj
    if not (inspect.isfunction(target) or inspect.isclass(target)):
        return None
    if not str(getattr(target, "__module__", "")).startswith(PACKAGES):
        return None
    if not (target.__doc__ or "").strip():
        logger.warning("a public name without a docstring: %s.%s",
                       target.__module__, target.__qualname__,
                       type="tegraph", subtype="undocumented")
    return None


def setup(app: Sphinx) -> dict[str, Any]:
    app.add_directive("tegraph-api", TegraphApi)
    app.connect("builder-inited", _note_described)
    app.connect("missing-reference", _resolve_alias)
    app.connect("missing-reference", _repository_file)
    app.connect("autodoc-skip-member", _undocumented)
    return {"parallel_read_safe": True, "parallel_write_safe": True}


def _repository_file(app: Sphinx, env: Any, node: Any, contnode: Any) -> Any:
    """A page's link to a file of the repository outside ``docs/`` (a results log of
    ``benchmarks/results/``) names that file: it is in the repository, not a page."""
    if node.get("refdomain") not in (None, "", "doc") and node.get("reftype") != "myst":
        return None
    target = str(node.get("reftarget", ""))
    path = (Path(app.srcdir) / Path(node.get("refdoc", "")).parent / target).resolve()
    root = Path(app.srcdir).resolve().parent
    for candidate in (path, path.with_suffix(".md")):
        if candidate.is_file() and root in candidate.parents and Path(app.srcdir).resolve() \
                not in candidate.parents:
            return nodes.literal(text=str(candidate.relative_to(root)))
    return None
