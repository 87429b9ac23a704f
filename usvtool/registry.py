"""Named classes of one kind (optimizers, controllers, scene families): the built-in ones and
those installed distributions declare under an entry-point group, in one mechanism.

A :class:`Registry` is a read-only mapping from a name to its class, in registration order:
the built-ins first, then the plugins of its ``group`` (``usvtool.planners``,
``usvtool.controllers``, ``usvtool.families``: ``name = "module:Class"`` in a distribution's
entry points), loaded on the first lookup. Two registries may share a group (``shares``: the
optimizers and the exact planners both come from ``usvtool.planners``): the group is loaded once
for both, each class going to the registry whose base it is a subclass of, and a name is one
method in the whole group. A plugin that fails to import, is not a subclass of a base of its
group, repeats a name or has a name the registry refuses is left out and named in one line
(:attr:`Registry.problems`, logged as a warning); every other method still works. A built-in's
name is the built-in's, whichever is registered first. :meth:`Registry.origin` says where a name
comes from (the distribution and its version), for ``usvtool plugins`` and the batch's keys.

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


class _Group:
    """The registries of one entry-point group, and its plugins' loading (once, for all)."""

    def __init__(self, name: str):
        self.name = name
        self.members: list[Registry] = []
        self.loaded = False
        self.problems: list[str] = []


class Registry(Mapping[str, type]):
    """The ``kind`` classes (subclasses of ``base``) by their ``name`` attribute; ``group``: the
    entry-point group of the plugins; ``refuse(cls)``: why a name cannot be registered (None when
    it can), beyond being new; ``shares``: a registry of the same group whose plugins and names
    this one shares (the group's classes of this one's base come here)."""

    def __init__(self, kind: str, base: type, group: str,
                 refuse: Callable[[type], str | None] = lambda cls: None,
                 shares: Registry | None = None):  # fmt: skip
        if shares is not None and shares.group != group:
            raise ValueError(f"{kind}: shares group {shares.group}, not {group}")
        self.kind, self.base, self.group, self._refuse = kind, base, group, refuse
        self._classes: dict[str, type] = {}
        self._origins: dict[str, tuple[str, str]] = {}
        self._where: dict[str, str] = {}  # a plugin's entry point, by name
        self._group = shares._group if shares is not None else _Group(group)
        self._group.members.append(self)

    @property
    def problems(self) -> list[str]:
        """One line for each plugin of the group left out, naming it and why."""
        return self._group.problems

    def register(self, cls: type, origin: tuple[str, str] | None = None, where: str = "") -> type:
        """Add ``cls`` under its ``name`` (``ValueError`` when the name is taken in the group,
        empty or refused, or ``cls`` is not a subclass of the base); returns ``cls``, so it also
        serves as a class decorator. ``origin``: (distribution, version), by default usvtool's
        (a built-in: a plugin holding its name gives way, named in :attr:`problems`);
        ``where``: a plugin's entry point, for that line."""
        name = getattr(cls, "name", None)
        if not (isinstance(cls, type) and issubclass(cls, self.base)):
            raise ValueError(f"{cls!r} is not a subclass of {self.base.__name__}")
        why = None if isinstance(name, str) and name else "no name"
        why = why or self._refuse(cls)
        holder = next((m for m in self._group.members if name in m._classes), None)
        if why is None and holder is not None:
            taken = f"{holder.kind} {name!r}: already registered (by {BUILT_IN})"
            if origin is None and holder._origins[name][0] != BUILT_IN:
                holder._problem(f"{holder._where.get(name, name)}: {taken}")
                holder.unregister(name)
            else:
                why = f"already registered (by {holder._origins[name][0]})"
        if why is not None:
            raise ValueError(f"{self.kind} {name!r}: {why}")
        self._classes[name] = cls
        self._origins[name] = origin or (BUILT_IN, __version__)
        if where:
            self._where[name] = where
        return cls

    def unregister(self, name: str) -> None:
        """Remove the class registered as ``name`` (KeyError when there is none)."""
        del self._classes[name]
        del self._origins[name]
        self._where.pop(name, None)

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
        """Register the plugins of the group, once for all its registries, sorted by name (the
        same order on every machine), each in the registry of its base; each one that cannot be
        is named in :attr:`problems`."""
        group = self._group
        if group.loaded:
            return
        group.loaded = True
        for point in sorted(metadata.entry_points(group=group.name), key=lambda p: p.name):
            dist = point.dist
            origin = (dist.name, dist.version) if dist is not None else ("?", "?")
            where = f"plugin {point.name} = {point.value} ({origin[0]} {origin[1]}, {group.name})"
            try:
                cls = point.load()
            except Exception as exc:  # a plugin's import may fail any way: left out, named
                self._problem(f"{where}: cannot be imported: {type(exc).__name__}: {exc}")
                continue
            # the members as they are now: a plugin's import may have added one (its module)
            kinds = [m for m in group.members if isinstance(cls, type) and issubclass(cls, m.base)]
            if not kinds:
                bases = " or ".join(m.base.__name__ for m in group.members)
                self._problem(f"{where}: {cls!r} is not a subclass of {bases}")
                continue
            try:
                kinds[0].register(cls, origin, where)
            except ValueError as exc:
                self._problem(f"{where}: {exc}")

    def _problem(self, line: str) -> None:
        self._group.problems.append(line)
        log.warning(line)
