"""The synchronization skeleton (spec §1): the class, its checks, its dictionary form.

``from tegraph.model.skeleton import Skeleton`` (and the elements ``Clock``,
``Link``, ``Protocol``, ``Task``) is how the rest of tegraph reaches it. The
modules, from the top down (each imports only those below it; the contract
"the skeleton sub-package" of ``pyproject.toml`` checks it, type-only
imports included):

==========  ==================================================================
``core``    :class:`Skeleton`, the dataclass: ``from_dict``, ``validate``,
            ``to_dict``, ``link_of_port``. A new field of the skeleton goes
            here, and into ``shape`` if the checks or the schema read it.
``schema``  The dictionary form (``skeleton_fields``, ``skeleton_to_data``):
            keys, number and name reading, per-value refusals. A new key of
            the file format goes here (and to ``docs/skeleton.md``).
``checks``  The cross-reference rules of spec §1 and §6 (``check_skeleton``,
            ``check_chain``) and the located errors (``Locator``, ``KeyPath``).
            A new rule relating two parts of a skeleton goes here, so that a
            file and a skeleton built in code obey it alike.
``shape``   :class:`~tegraph.model.skeleton.shape.SkeletonShape`, the
            ``typing.Protocol`` of what ``checks`` and ``schema`` read of a
            skeleton: they are typed against it, never against ``core``.
==========  ==================================================================

The element dataclasses themselves (``Clock``, ``Task``, ``Link``,
``Protocol``) are :mod:`tegraph.model.elements`; reading and writing files is
:mod:`tegraph.io.skeleton_file`.
"""

from ..elements import Clock, Link, Protocol, Task
from .core import Skeleton

__all__ = ["Clock", "Link", "Protocol", "Skeleton", "Task"]
