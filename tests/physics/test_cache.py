"""numba's caches dropped when a compiled source changes (:mod:`pde_rotor.physics.cache`)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

from pde_rotor.physics.cache import COMPILED_SOURCES, STAMP, refresh_caches, source_digest

PACKAGE = Path(__file__).resolve().parents[2] / "pde_rotor"


def _tree(root: Path) -> list[Path]:
    """A package with compiled sources and a cache file beside each, and a folder that
    compiled code does not read; returns the cache files."""
    for name in ("physics/tension.py", "kernels/body_sums.py", "model/body_schemes.py",
                 "config/numerics.py", "sweep/cost.py"):  # fmt: skip
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(f"# {name}\n")
    caches = []
    for name in ("kernels/__pycache__/body_sums.circle-1.py311.nbi",
                 "kernels/__pycache__/body_sums.circle-1.py311.1.nbc",
                 "physics/__pycache__/build.cpu_jit-2.py311.nbi"):  # fmt: skip
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(b"compiled")
        caches.append(path)
    return caches


def test_caches_go_when_a_compiled_source_changes_and_stay_otherwise(tmp_path: Path) -> None:
    """No digest yet: the caches go and the digest is stored; the same sources: they stay;
    a changed tension (the callee a cached loop of another file inlines): they go; a
    changed file outside the compiled folders, or a byte code file: they stay."""
    caches = _tree(tmp_path)
    bytecode = tmp_path / "kernels" / "__pycache__" / "body_sums.cpython-311.pyc"
    bytecode.write_bytes(b"pyc")
    assert refresh_caches(tmp_path) == 3
    assert not any(path.exists() for path in caches) and bytecode.exists()
    assert (tmp_path / "__pycache__" / STAMP).read_text() == source_digest(tmp_path)
    _tree(tmp_path)
    assert refresh_caches(tmp_path) == 0
    assert all(path.exists() for path in caches)
    (tmp_path / "sweep" / "cost.py").write_text("# edited\n")
    assert refresh_caches(tmp_path) == 0
    (tmp_path / "physics" / "tension.py").write_text("# edited: a new surface pressure\n")
    assert refresh_caches(tmp_path) == 3
    assert not any(path.exists() for path in caches)


def test_the_digest_reads_paths_and_contents(tmp_path: Path) -> None:
    """Moving a file's contents to another compiled file changes the digest; so does one
    byte of a module in any compiled folder."""
    _tree(tmp_path)
    first = source_digest(tmp_path)
    (tmp_path / "model" / "body_schemes.py").write_text("# model/body_schemes.pz\n")
    assert source_digest(tmp_path) != first
    for folder in COMPILED_SOURCES:
        assert (PACKAGE / folder).is_dir()


def _module(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, modules: dict[str, Path]) -> set[str]:
    """The package's modules that `path` imports (relative or absolute)."""
    here = _module(path)
    package = here if path.name == "__init__.py" else here.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - max(node.level - 1, 0)]
            target = ".".join([*base, node.module] if node.module else base)
            if not node.level:
                target = node.module or ""
            found |= {t for t in (target, *(f"{target}.{a.name}" for a in node.names))
                      if t in modules}  # fmt: skip
        elif isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name in modules}
    return found


def test_compiled_code_reads_only_the_digested_folders() -> None:
    """Every module that compiles (defines a function for numba's ``njit`` or
    ``cuda.jit``) and every module of the package it imports, directly or not, lies in a
    :data:`COMPILED_SOURCES` folder (or is the package's face), so that the digest covers
    whatever a cached loop inlines or froze."""
    modules = {_module(path): path for path in PACKAGE.rglob("*.py")}
    compiled = [name for name, path in modules.items()
                if re.search(r"njit|cuda\.jit|cpu_jit", path.read_text("utf-8"))]  # fmt: skip
    assert {"pde_rotor.kernels.body_sums", "pde_rotor.physics.build"} <= set(compiled)
    seen: set[str] = set()
    stack = list(compiled)
    while stack:
        name = stack.pop()
        if name not in seen:
            seen.add(name)
            stack.extend(_imports(modules[name], modules))
    faces = {"pde_rotor", "pde_rotor._lazy", "pde_rotor._version"}
    outside = sorted(n for n in seen - faces if n.split(".")[1] not in COMPILED_SOURCES)
    assert not outside
    assert seen >= {"pde_rotor.physics.tension", "pde_rotor.model.body_schemes"}
