"""The command-line reference, from typer's own command tree (what ``--help`` prints).

``.. tegraph-cli::`` walks ``typer.main.get_command(tegraph.cli.app)``: the group's
help, then for each command its usage line, its help and each argument and option
with typer's own help record (the default, the metavar, whether it is required).
The text is set as plain text, not parsed: a help string's backquotes and
asterisks read as the terminal shows them; option names are set as literals.

The tree is taken once, when the builder starts, before autodoc reads any module:
autodoc's ``autodoc_preserve_defaults`` gives each documented function a
``__signature__`` of unevaluated annotations, in which typer would no longer find
the options' ``Annotated`` declarations.
"""

from __future__ import annotations

from typing import Any

import typer
from docutils import nodes
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective


def _paragraphs(text: str) -> list[nodes.Node]:
    return [nodes.paragraph(text=" ".join(block.split()))
            for block in (text or "").split("\n\n") if block.strip()]


def _section(title: str, ident: str) -> nodes.section:
    section = nodes.section(ids=[ident])
    section += nodes.title(text=title)
    return section


class TegraphCli(SphinxDirective):
    """``.. tegraph-cli::``: a section per command of ``tegraph``."""

    def run(self) -> list[nodes.Node]:
        group = self.env.app.tegraph_cli_group  # type: ignore[attr-defined]
        context = group.context_class(group, info_name="tegraph")
        out: list[nodes.Node] = [*_paragraphs(group.help or ""),
                                 nodes.literal_block(text=group.get_usage(context))]
        for name, command in group.commands.items():
            sub = command.context_class(command, info_name=name, parent=context)
            section = _section(f"tegraph {name}", nodes.make_id(f"tegraph-{name}"))
            section += nodes.literal_block(text=command.get_usage(sub))
            section += _paragraphs(command.help or "")
            items = nodes.definition_list()
            for param in command.params:
                record = param.get_help_record(sub)
                if record is None:  # a hidden option
                    continue
                term, help_text = record
                item = nodes.definition_list_item()
                item += nodes.term("", "", nodes.literal(text=term))
                definition = nodes.definition()
                definition += _paragraphs(help_text) or [nodes.paragraph(text="")]
                item += definition
                items += item
            section += items
            out.append(section)
        return out


def _command_tree(app: Sphinx) -> None:
    from tegraph.cli import app as cli_app

    app.tegraph_cli_group = typer.main.get_command(cli_app)  # type: ignore[attr-defined]


def setup(app: Sphinx) -> dict[str, Any]:
    app.connect("builder-inited", _command_tree)
    app.add_directive("tegraph-cli", TegraphCli)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
