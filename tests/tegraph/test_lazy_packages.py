"""``tegraph.io`` and ``tegraph.report`` import their modules on first use, API unchanged.

A skeleton's ``analyze --json`` needs neither the readers of the other formats nor
the text report (and tabulate): the packages name them as before, and importing
them happens when a name is first asked for.
"""

import importlib
import subprocess
import sys
from pathlib import Path

import pytest

import tegraph.io
import tegraph.report

ROOT = Path(__file__).resolve().parents[2]


def _loaded(code: str) -> list[str]:
    """The tegraph modules and tabulate loaded by ``code`` in a fresh interpreter."""
    done = subprocess.run(
        [sys.executable, "-c", "import sys; sys.path.insert(0, '.')\n" + code + "\n"
         "print(' '.join(m for m in sys.modules if m.startswith(('tegraph', 'tabulate'))))"],
        cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout.split()


@pytest.mark.parametrize("name", ["dot", "edges", "pnml", "sdf3", "tpne"])
def test_the_format_modules_are_attributes_of_tegraph_io(name):
    assert tegraph.io.__getattr__(name) is importlib.import_module(f"tegraph.io.{name}")
    assert getattr(tegraph.io, name) is sys.modules[f"tegraph.io.{name}"]
    assert name in dir(tegraph.io)


@pytest.mark.parametrize("package", [tegraph.io, tegraph.report])
def test_the_package_names_are_those_of_its_table(package):
    assert sorted(package.__all__) == sorted(package._WHERE)
    assert set(package.__all__) <= set(dir(package))


@pytest.mark.parametrize("package, name", [(p, n) for p in (tegraph.io, tegraph.report)
                                           for n in p.__all__])
def test_each_package_name_is_its_module_s_object(package, name):
    module = importlib.import_module(package._WHERE[name])
    assert getattr(package, name) is getattr(module, name)


def test_unknown_names_are_refused():
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        tegraph.io.nothing  # noqa: B018
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        tegraph.report.nothing  # noqa: B018


def test_reading_a_skeleton_loads_no_other_format():
    loaded = _loaded("from tegraph.io import load_skeleton\n"
                     "load_skeleton('examples/computed_torque.yaml')")
    assert not [m for m in loaded if m.startswith(("tegraph.io.", "tegraph.model.petri",
                                                   "tegraph.model.sdf"))
                and m not in ("tegraph.io.skeleton_file", "tegraph.io._skeleton_yaml",
                              "tegraph.io.formats", "tegraph.io._files")]


def test_a_json_report_loads_no_text_report():
    loaded = _loaded("from tegraph.report import to_json\n"
                     "from tegraph.api import analyze\n"
                     "print(to_json(analyze('examples/computed_torque.yaml'))[:0])")
    assert "tegraph.report.document" in loaded
    for module in ("tabulate", "tegraph.report.text", "tegraph.report.tables",
                   "tegraph.report.dot", "tegraph.io.dot"):
        assert module not in loaded, module


def test_a_json_skeleton_is_read_without_pyyaml(tmp_path):
    """PyYAML is imported for YAML text only (and for the lines of a refused JSON file)."""
    path = tmp_path / "s.json"
    path.write_text('{"tasks": {"A": {"duration": 1, "period": 3, "outputs": ["x"]},'
                    ' "B": {"duration": "1/2", "inputs": ["x"]}},'
                    ' "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]}')
    done = subprocess.run(
        [sys.executable, "-c", "import sys; sys.path.insert(0, '.')\n"
         "from tegraph.api import analyze\n"
         "from tegraph.report import to_json\n"
         f"to_json(analyze({str(path)!r}))\n"
         "print('yaml' in sys.modules)"],
        cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["False"]
