"""Run the gallery: the scripts in gallery/ that reproduce the paper's figures.

Every ``gallery/<name>.py`` is a thin gallery script with a function
``main(argv) -> list[Path]`` that accepts ``[--quick | --tiny] --out DIR
[--scheduler ADDRESS]`` (:mod:`.common`) and writes its figures as PNG and PDF (the
movie script also an mp4 and a GIF) into DIR; what the scripts share is this package
(:mod:`.common`, :mod:`.sweeps`, :mod:`.timeseries`). :func:`run_gallery`
discovers the scripts, runs the selected ones one after the other in this process (the
compiled kernels are shared) and collects what they wrote; ``pde-rotor gallery`` calls it.

The scripts live in the repository (gallery/), not in the installed package: the gallery
runs from a source checkout (``pip install -e .``).
"""

from __future__ import annotations

import importlib.util
import logging
import shutil
import sys
import time
import traceback
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType

from .common import GALLERY

_logger = logging.getLogger(__name__)

PUBLISHED_SUFFIXES = (".png", ".gif")
"""Files that :func:`publish_files` copies from the output directory into gallery/."""


class GalleryError(RuntimeError):
    """The gallery cannot run (no gallery directory, unknown script); one line."""


def gallery_dir() -> Path:
    """The gallery/ directory of the source checkout this package runs from.

    Raises:
        GalleryError: the package is not installed from a checkout with gallery/.
    """
    path = GALLERY
    if not any(path.glob("fig*.py")):
        msg = (
            f"no gallery scripts at {path}: the gallery runs from a source checkout "
            "(git clone ...; pip install -e .)"
        )
        raise GalleryError(msg)
    return path


def scripts(directory: Path | None = None) -> dict[str, Path]:
    """Gallery scripts by name (file stem), sorted: every ``*.py`` of the directory."""
    directory = directory if directory is not None else gallery_dir()
    return {p.stem: p for p in sorted(directory.glob("*.py")) if not p.name.startswith("_")}


def select(available: Iterable[str], only: Sequence[str] | None) -> list[str]:
    """The script names matching `only` (all if None or empty).

    A pattern matches a name equal to it or one of whose ``_``-separated words it
    begins (``fig5`` -> fig5_probability, ``fig6`` -> fig4_fig6_timeseries, ``movie``
    -> movie_inversion).

    Raises:
        GalleryError: a pattern matches no script (the message lists the names).
    """
    names = list(available)
    if not only:
        return names
    chosen: list[str] = []
    for pattern in only:
        hits = [n for n in names if n == pattern or f"_{pattern}_" in f"_{n}_"]
        if not hits:
            msg = f"--only {pattern!r} matches no gallery script (available: {', '.join(names)})"
            raise GalleryError(msg)
        chosen += [h for h in hits if h not in chosen]
    return [n for n in names if n in chosen]


def load_script(path: Path) -> ModuleType:
    """Import a gallery script as a module (it imports only the installed package)."""
    spec = importlib.util.spec_from_file_location(f"pde_rotor_gallery_{path.stem}", path)
    if spec is None or spec.loader is None:
        msg = f"cannot import {path}"
        raise GalleryError(msg)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while it executes
    try:
        spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(spec.name, None)
        raise
    if not callable(getattr(module, "main", None)):
        msg = f"{path} has no main(argv) function"
        raise GalleryError(msg)
    return module


@dataclass
class GalleryResult:
    """What :func:`run_gallery` did.

    Attributes:
        out: output directory.
        files: files written, by script name.
        seconds: wall time by script name.
        failed: error message by script name.
    """

    out: Path
    files: dict[str, list[Path]] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)
    failed: dict[str, str] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """Whether every selected script succeeded."""
        return not self.failed


@contextmanager
def _local_scheduler(threads: bool) -> Iterator[str | None]:
    """An in-process dask cluster shared by all sweeps of a tiny run (None if not `threads`)."""
    if not threads:
        yield None
        return
    from distributed import LocalCluster

    cluster = LocalCluster(
        n_workers=1,
        threads_per_worker=1,
        processes=False,
        dashboard_address=None,
        silence_logs=logging.ERROR,
    )
    try:
        yield cluster.scheduler_address
    finally:
        cluster.close()


def run_gallery(
    quick: bool,
    only: list[str] | None,
    out: Path,
    *,
    tiny: bool = False,
    scheduler: str | None = None,
    publish: bool = False,
) -> GalleryResult:
    """Run the selected gallery scripts one after the other.

    Args:
        quick: coarse grid and few samples (``--quick``); False: full fidelity.
        only: script names or prefixes (``["fig5", "movie"]``); None: all.
        out: output directory of the figures.
        tiny: smoke-test size (overrides `quick`); its sweeps share one in-process
            dask cluster unless `scheduler` is given.
        scheduler: address of a running dask scheduler for the sweeps.
        publish: copy each PNG and GIF written into gallery/ (the committed images);
            refused for tiny runs.

    Returns:
        Files written, wall times and failures (a failing script does not stop the others).

    Raises:
        GalleryError: no gallery directory, an unknown name in `only`, or publish with tiny.
    """
    if publish and tiny:
        msg = "refusing to publish tiny (smoke-test) images into gallery/"
        raise GalleryError(msg)
    directory = gallery_dir()
    available = scripts(directory)
    names = select(available, only)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    mode = ["--tiny"] if tiny else ["--quick"] if quick else []
    result = GalleryResult(out=out)
    with _local_scheduler(tiny and scheduler is None) as local:
        address = scheduler or local
        for name in names:
            argv = [*mode, "--out", str(out)]
            if address:
                argv += ["--scheduler", address]
            _logger.info("gallery: %s %s", name, " ".join(argv))
            start = time.perf_counter()
            try:
                module = load_script(available[name])
                written = module.main(argv)
            except Exception as err:  # keep going: report every failing script
                result.failed[name] = f"{type(err).__name__}: {err}"
                _logger.error("gallery: %s failed:\n%s", name, traceback.format_exc())
                written = []
            result.seconds[name] = time.perf_counter() - start
            result.files[name] = [Path(p) for p in written or []]
    if publish:
        for name, files in result.files.items():
            if name not in result.failed:
                publish_files(files, directory)
    return result


def publish_files(files: Iterable[Path], directory: Path | None = None) -> list[Path]:
    """Copy the PNGs and GIFs among `files` into gallery/ (the committed images)."""
    directory = directory if directory is not None else gallery_dir()
    copied = []
    for path in files:
        if path.suffix in PUBLISHED_SUFFIXES and path.resolve().parent != directory:
            target = directory / path.name
            shutil.copyfile(path, target)
            copied.append(target)
    return copied
