"""A scene as an ordinary scenario file: its YAML (a comment header saying which scene it is and
how many draws it took) and, beside it, the files it names (``<stem>.map.tif``,
``<stem>.wind.tif``, a replayed target's ``<stem>.ais-MMSI.csv``), written all or none
(:class:`usvtool.atomic.staged`)."""

from __future__ import annotations

import copy
from pathlib import Path

import yaml

from usvtool.sim.families.base import Scene
from usvtool.yamlfile import comment


def scene_files(scene: Scene, path: str | Path) -> list[Path]:
    """The files :func:`write_scene` writes for ``scene`` at ``path``: the scenario, then the
    files it names."""
    path = Path(path)
    return [path, *(_beside(path, suffix) for suffix, _ in scene.draw.files.values())]


def scene_text(scene: Scene, stem: str) -> str:
    """The scenario file's text, the files it names as ``<stem>.<suffix>``."""
    mapping = copy.deepcopy(scene.draw.scenario)
    for where, (suffix, _) in scene.draw.files.items():
        *parents, key = (int(p) if p.isdigit() else p for p in where.split("."))
        holder = mapping
        for p in parents:
            holder = holder[p]
        holder[key] = f"{stem}.{suffix}"
    given = ", ".join(f"{k}={v}" for k, v in sorted(scene.given.items())) or "none"
    rejected = ", ".join(f"{n} {r}" for r, n in sorted(scene.rejected.items())) or "none"
    header = [comment(line) for line in (  # an option's value may hold a line break
        f"Scene {scene.scene} of kind {scene.kind} of the scene family {scene.family} "
        "(docs/families.md);",
        f"options given: {given}; draw {scene.draws} (rejected: {rejected}).",
        f"Written again by: usvtool scene --family {scene.family} --kind {scene.kind} --scene "
        f"{scene.scene}" + "".join(f" --family-option {k}={v}" for k, v in
                                   sorted(scene.given.items())) + " -o FILE",
        *scene.draw.comments,
    )]  # fmt: skip
    body = yaml.safe_dump(mapping, sort_keys=False, default_flow_style=None, width=100)
    return "\n".join(header) + "\n" + body


def write_scene(scene: Scene, path: str | Path) -> list[Path]:
    """Write ``scene`` as the scenario file ``path`` and its files beside it, all or none;
    the files written (:func:`scene_files`)."""
    from usvtool.atomic import staged

    files = scene_files(scene, path)
    writers = [w for _, w in scene.draw.files.values()]
    with staged(*files) as (text_tmp, *raster_tmps):
        Path(text_tmp).write_text(scene_text(scene, Path(path).stem), encoding="utf-8")
        for writer, tmp in zip(writers, raster_tmps, strict=True):
            writer.write(tmp)
    return files


def _beside(path: Path, suffix: str) -> Path:
    return path.with_name(f"{path.stem}.{suffix}")
