"""Named classes of one kind (optimizers, controllers, scene families): the built-in ones and
those installed distributions declare under an entry-point group, in one mechanism.

A :class:`Registry` is a read-only mapping from a name to its class, in registration order:
the built-ins first, then the plugins of its ``group`` (``usvtool.planners``,
``usvtool.controllers``, ``usvtool.families``: ``name = "module:Class"`` in a distribution's
entry points), loaded on the first lookup. A plugin that fails to import, is not a subclass of
the registry's base, repeats a name or has a name the registry refuses is left out and named
in one line (:attr:`Registry.problems`, logged as a warning); every other method still works.
:meth:`Registry.origin` says where a name comes from (the distribution and its version), for
``usvtool plugins`` and the batch's keys.

Hand-written: the entry-point plumbing is ``importlib.metadata``'s; what is added is the
checks and one place for the three kinds (they were three dicts with their own rules).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterator, Mapping
from importlib import metadata

from usvtool import __version__

log = logging.getLogger("usvtool")

#: Where a built-in class comes from (:meth:`Registry.origin`).
BUILT_IN = "usvtool"


class Registry(Mapping[str, type]):
    """The ``kind`` classes (subclasses of ``base``) by their ``name`` attribute; ``group``: the
    entry-point group of the plugins; ``refuse(cls)``: why a name cannot be registered (None when
    it can), beyond being new."""

    def __init__(self, kind: str, base: type, group: str,
                 refuse: Callable[[type], str | None] = lambda cls: None):  # fmt: skip
        self.kind, self.base, self.group, self._refuse = kind, base, group, refuse
        self._classes: dict[str, type] = {}
        self._origins: dict[str, tuple[str, str]] = {}
        self._loaded = False
        #: One line for each plugin left out, naming it and why.
        self.problems: list[str] = []

    def register(self, cls: type, origin: tuple[str, str] | None = None) -> type:
        """Add ``cls`` under its ``name`` (``ValueError`` when the name is taken, empty or
        refused, or ``cls`` is not a subclass of the base); returns ``cls``, so it also serves
        as a class decorator. ``origin``: (distribution, version), by default usvtool's."""
        name = getattr(cls, "name", None)
        if not (isinstance(cls, type) and issubclass(cls, self.base)):
            raise ValueError(f"{cls!r} is not a subclass of {self.base.__name__}")
        why = None if isinstance(name, str) and name else "no name"
        why = why or self._refuse(cls)
        if why is None and name in self._classes:
            why = f"already registered (by {self.origin(name)[0]})"
        if why is not None:
            raise ValueError(f"{self.kind} {name!r}: {why}")
        self._classes[name] = cls
        self._origins[name] = origin or (BUILT_IN, __version__)
        return cls

    def unregister(self, name: str) -> None:
        """Remove the class registered as ``name`` (KeyError when there is none)."""
        del self._classes[name]
        del self._origins[name]

    def origin(self, name: str) -> tuple[str, str]:
        """(distribution, version) that ``name`` comes from."""
        self._load()
        return self._origins[name]

    def __getitem__(self, name: str) -> type:
        self._load()
        return self._classes[name]

    def __iter__(self) -> Iterator[str]:
        self._load()
        return iter(list(self._classes))

    def __len__(self) -> int:
        self._load()
        return len(self._classes)

    def _load(self) -> None:
        """Register the plugins of :attr:`group`, once, sorted by name (the same order on every
        machine); each one that cannot be is named in :attr:`problems`."""
        if self._loaded:
            return
        self._loaded = True
        for point in sorted(metadata.entry_points(group=self.group), key=lambda p: p.name):
            dist = point.dist
            origin = (dist.name, dist.version) if dist is not None else ("?", "?")
            where = f"plugin {point.name} = {point.value} ({origin[0]} {origin[1]}, {self.group})"
            try:
                cls = point.load()
            except Exception as exc:  # a plugin's import may fail any way: left out, named
                self._problem(f"{where}: cannot be imported: {type(exc).__name__}: {exc}")
                continue
            try:
                self.register(cls, origin)
            except ValueError as exc:
                self._problem(f"{where}: {exc}")

    def _problem(self, line: str) -> None:
        self.problems.append(line)
        log.warning(line)

