"""numba's on-disk caches of the package's compiled loops, dropped when their sources change.

numba keys a cached loop by the file that defines it (its modification time and size),
not by the functions it inlines from other modules nor by the module-level constants it
froze when it was compiled. After an edit of ``physics/tension.py`` alone (a ``git pull``
into an editable install, say), a loop of ``kernels/body_sums.py`` that inlines the
tension would load its old machine code from the cache and run the old physics without a
word. :func:`refresh_caches`, run once when :mod:`pde_rotor.physics.build` is first
imported (before any loop is compiled or loaded), keeps a digest of every source file that
compiled code reads (:data:`COMPILED_SOURCES`) beside the caches, and where it no longer
matches deletes every cache file under the package, so that each loop is compiled anew
once. A cache that numba keeps outside the package (``NUMBA_CACHE_DIR``, or the
user-wide directory of a read-only install, which a reinstall refreshes whole) is left to
numba.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

COMPILED_SOURCES = ("config", "kernels", "model", "physics")
"""The folders of the package whose modules compiled code defines, inlines or reads
constants from (``tests/physics/test_cache.py`` follows the imports of every module that
compiles to check that none reaches outside them)."""

CACHE_SUFFIXES = (".nbi", ".nbc")
"""numba's index and data files of a cached loop."""

STAMP = "numba-sources.sha256"
"""The file, in the package's top ``__pycache__``, holding the digest the caches were
made from."""


def source_digest(root: Path) -> str:
    """The SHA-256 of every ``.py`` file of `root`'s :data:`COMPILED_SOURCES` folders, path
    and contents, in sorted order."""
    digest = hashlib.sha256()
    for folder in COMPILED_SOURCES:
        for path in sorted((root / folder).rglob("*.py")):
            digest.update(path.relative_to(root).as_posix().encode())
            digest.update(b"\0")
            digest.update(path.read_bytes())
    return digest.hexdigest()


def refresh_caches(root: Path) -> int:
    """Delete numba's cache files under the package `root` if its compiled sources changed.

    The digest of :func:`source_digest` is compared with the one stored in
    ``root/__pycache__/`` (:data:`STAMP`); where it differs or is missing, every
    :data:`CACHE_SUFFIXES` file in a ``__pycache__`` under `root` is deleted and the new
    digest stored (written whole, then renamed, so that a process starting beside this one
    reads the old digest or the new one). A package it may not write to is left as it is.

    Returns:
        The number of cache files deleted.
    """
    digest = source_digest(root)
    stamp = root / "__pycache__" / STAMP
    try:
        if stamp.read_text(encoding="ascii") == digest:
            return 0
    except OSError:
        pass
    removed = 0
    for path in root.rglob("__pycache__/*"):
        if path.suffix in CACHE_SUFFIXES:
            try:
                path.unlink()
                removed += 1
            except OSError:
                pass
    try:
        stamp.parent.mkdir(exist_ok=True)
        fresh = stamp.with_name(f"{STAMP}.{os.getpid()}")
        fresh.write_text(digest, encoding="ascii")
        os.replace(fresh, stamp)
    except OSError:
        pass
    return removed
