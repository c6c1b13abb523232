"""Docs that cannot drift: every file, test and ``module.Name`` they name exists.

The pages (README.md, docs/*.md, gallery/README.md, tests/README.md) and the package's
docstrings and comments name files (``pde_rotor/sweep/plan.py``, ``data/fig9.nc``),
tests (``tests/theory/test_dish.py::test_walls_push_and_pull``) and Python objects
(``pde_rotor.sweep.tasks.warm_state``, ``sweep.tasks.execute_group``, ``Timing.of``,
``:func:`.restart.draw_stop```). Each must exist: a path in the repository, a test
function (or class) in that file, an object reached by importing the module and
following the attributes. A dotted name that does not start with a module or a
top-level name of the package (``np.sqrt``, ``ds.omega``) or that is a config key
(``grid.dx``, ``config.noise.sigma``) is no reference to the code and is left alone.
Placeholders (``data/sweeps/<name>``, ``configs/sweeps/*.yaml``, ``data/NAME.nc``) are
not paths, and neither are the paths the code writes (a folder .gitignore names, the
default store ``data/sweeps/<name>`` of a shipped sweep file).
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import inspect
import io
import re
import tokenize
from collections import defaultdict
from functools import cache
from pathlib import Path

import pytest
from pydantic import BaseModel

from pde_rotor.config import RotorConfig

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "pde_rotor"
PAGES = [
    ROOT / "README.md",
    *sorted((ROOT / "docs").glob("*.md")),
    ROOT / "gallery" / "README.md",
    ROOT / "tests" / "README.md",
]
MODULES = sorted(PACKAGE.rglob("*.py"))

FOLDERS = ("pde_rotor", "tests", "docs", "gallery", "benchmarks", "configs", "data", "examples")
PATH = re.compile(rf"(?<![\w./-])((?:{'|'.join(FOLDERS)})/[\w./-]*[\w/])((?:::[\w]+)*)(?![\w<*{{])")
"""A repository path, optionally with ``::test`` parts; not followed by a placeholder."""
DOTTED = re.compile(r"~?\.?[A-Za-z_]\w*(?:\.[A-Za-z_]\w*)*")
PREFIXED = re.compile(r"(?<![\w./])pde_rotor(?:\.[A-Za-z_]\w*)+")
BACKTICKED = re.compile(r"(?<!`)`([^`\n]+)`(?!`)")
LITERAL = re.compile(r"``([^`\n]+)``")
ROLE = re.compile(r":(?:func|class|mod|meth|attr|data|obj|exc):`([^`]+)`")
FILE_SUFFIX = re.compile(
    r"\.(py|ya?ml|nc|h5|png|gif|mp4|csv|md|jsonl?|txt|ipynb|tex|toml|sh|log|pdf|svg|npz|npy"
    r"|zarr|html|part|lock)(\.|$)"
)
"""A file name (``config.yaml``, ``movie.mp4.part``), not a reference."""


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


@cache
def top_level_names() -> dict[str, set[str]]:
    """Each first component an unprefixed reference may start with, and the full dotted
    names it may stand for: the package's modules by their trailing parts, and the
    classes and functions defined at the top of a module."""
    names: dict[str, set[str]] = defaultdict(set)
    for path in MODULES:
        name = module_name(path)
        parts = name.split(".")
        for i in range(1, len(parts)):
            names[parts[i]].add(".".join(parts[: i + 1]))
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, (ast.ClassDef, ast.FunctionDef)) and not node.name.startswith("_"):
                names[node.name].add(f"{name}.{node.name}")
    return names


MISSING = object()


def _attribute(obj: object, name: str) -> object:
    """obj.name, True for a field or instance attribute of a class obj, else MISSING."""
    if hasattr(obj, name):
        return getattr(obj, name)
    if inspect.isclass(obj):
        if issubclass(obj, BaseModel) and name in obj.model_fields:
            return obj.model_fields[name].annotation or True
        for klass in obj.__mro__:
            if name in getattr(klass, "__dataclass_fields__", {}) or name in vars(klass).get(
                "__annotations__", {}
            ):
                return True
            try:
                source = inspect.getsource(klass)
            except (OSError, TypeError):
                continue
            if re.search(rf"\bself\.{name}\b\s*(?::[^=]+)?=", source):
                return True
    return MISSING


@cache
def installed(package: str) -> bool:
    """Whether `package` is pde_rotor or an installed library (never a script on the path)."""
    if package == "pde_rotor":
        return True
    try:
        spec = importlib.util.find_spec(package)
    except (ImportError, ValueError):
        return False
    return bool(spec and spec.origin and "site-packages" in spec.origin)


@cache
def resolves(dotted: str) -> bool:
    """Whether ``pde_rotor.x.y.Name.attr`` (or ``scipy.special.kve``) names a module or an
    object reached from one; only pde_rotor and installed libraries are imported."""
    parts = dotted.split(".")
    if not installed(parts[0]):
        return False
    for i in range(len(parts), 0, -1):
        try:
            obj: object = importlib.import_module(".".join(parts[:i]))
        except ModuleNotFoundError:
            continue
        for name in parts[i:]:
            obj = _attribute(obj, name)
            if obj is MISSING:
                return False
        return True
    return False


@cache
def config_key(dotted: str) -> bool:
    """Whether `dotted` is a config key (``grid.dx``), also written ``config.grid.dx``
    or as an attribute of an object's config (``pde.config.noise.seed``)."""
    parts = dotted.split(".")
    starts = [0] + [i + 1 for i, part in enumerate(parts[:-1]) if part in ("config", "cfg")]
    for start in starts:
        model: object = RotorConfig
        for depth, name in enumerate(parts[start:]):
            fields = getattr(model, "model_fields", {})
            if name in fields:
                model = fields[name].annotation
            elif depth > 0 and isinstance(getattr(model, name, None), property):
                model = None
            else:
                break
        else:
            if len(parts) - start >= 1 and parts[start] in RotorConfig.model_fields:
                return True
    return False


def check_dotted(text: str, context: str | None = None, role: bool = False) -> str | None:
    """The failure of one dotted reference, or None when it resolves or is none.

    Args:
        text: the reference (``~`` and a leading ``.`` allowed, ``()`` stripped).
        context: the module it is written in: bare and relative names resolve there.
        role: a Sphinx role (``:func:`name```): a reference even as a bare name, which
            may then be defined anywhere in the package or be an importable object.
    """
    text = text.strip().removesuffix("()").lstrip("~")
    if not DOTTED.fullmatch(text) or FILE_SUFFIX.search(text):
        return None
    if text.startswith("pde_rotor."):
        return None if resolves(text) else text
    if text.startswith("."):
        if not (context and role):
            return None
        package = context if is_package(context) else context.rpartition(".")[0]
        candidates = {f"{package}{text}", f"{context}{text}"}
        return None if any(resolves(c) for c in candidates) else text
    if config_key(text) or resolves(text):
        return None
    head, _, rest = text.partition(".")
    if not rest and not role:
        return None
    starts = set(top_level_names().get(head, ()))
    if context and resolves(f"{context}.{head}"):
        starts.add(f"{context}.{head}")
    if not starts:
        if role and not rest and head in defined_names():
            return None
        return text if role else None
    candidates = {f"{start}.{rest}" if rest else start for start in starts}
    return None if any(resolves(c) for c in candidates) else text


@cache
def defined_names() -> set[str]:
    """Every function, class and assigned name of the package, nested ones too."""
    names = set()
    for path in MODULES:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                names.add(node.name)
            elif isinstance(node, (ast.Assign, ast.AnnAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                names |= {n.id for n in targets if isinstance(n, ast.Name)}
    return names


@cache
def is_package(module: str) -> bool:
    return (ROOT / Path(*module.split(".")) / "__init__.py").exists()


PLACEHOLDER = re.compile(r"(?<![A-Za-z])NAME(?![A-Za-z])")
"""``configs/sweeps/NAME.yaml``: any file of that form."""


@cache
def ignored_folders() -> tuple[str, ...]:
    """The folders .gitignore names (``gallery/output/``): what running the code writes."""
    lines = (ROOT / ".gitignore").read_text(encoding="utf-8").splitlines()
    return tuple(line.lstrip("/") for line in lines if line.endswith("/") and "*" not in line)


def produced(path: str) -> bool:
    """A path the code writes rather than one in the repository: inside an ignored folder,
    or the default store ``data/sweeps/<name>`` of a shipped sweep file."""
    parts = Path(path).parts
    if parts[:2] == ("data", "sweeps") and len(parts) > 2:
        return (ROOT / "configs" / "sweeps" / f"{parts[2]}.yaml").exists()
    return any(f"{path.rstrip('/')}/".startswith(folder) for folder in ignored_folders())


def check_path(path: str, tests: str) -> str | None:
    """The failure of a repository path (and its ``::test`` parts), or None."""
    target = ROOT / path
    if PLACEHOLDER.search(path) or (not target.exists() and produced(path)):
        return None
    if not target.exists():
        return path + tests
    if not tests:
        return None
    tree = ast.parse(target.read_text(encoding="utf-8"))
    scope: list[ast.stmt] = tree.body
    for name in tests.strip(":").split("::"):
        found = next(
            (n for n in scope if isinstance(n, (ast.FunctionDef, ast.ClassDef)) and n.name == name),
            None,
        )
        if found is None:
            return path + tests
        scope = found.body
    return None


def page_failures(text: str) -> list[str]:
    """Stale paths and references of a Markdown page."""
    failures = [check_path(p, t) for p, t in PATH.findall(text)]
    failures += [check_dotted(span) for span in BACKTICKED.findall(text)]
    failures += [check_dotted(name.rstrip(".")) for name in PREFIXED.findall(text)]
    return [f for f in failures if f]


def source_texts(path: Path) -> tuple[list[str], list[str]]:
    """The docstrings (every string statement) and the comments of a Python file."""
    source = path.read_text(encoding="utf-8")
    strings = [
        node.value.value
        for node in ast.walk(ast.parse(source))
        if isinstance(node, ast.Expr)
        and isinstance(node.value, ast.Constant)
        and isinstance(node.value.value, str)
    ]
    comments = [
        token.string
        for token in tokenize.generate_tokens(io.StringIO(source).readline)
        if token.type == tokenize.COMMENT
    ]
    return strings, comments


def source_failures(path: Path) -> list[str]:
    """Stale paths and references of a module's docstrings and comments."""
    context = module_name(path)
    strings, comments = source_texts(path)
    failures = []
    for text in strings:
        failures += [check_path(p, t) for p, t in PATH.findall(text)]
        failures += [check_dotted(ref, context, role=True) for ref in ROLE.findall(text)]
        failures += [check_dotted(span, context) for span in LITERAL.findall(text)]
        failures += [check_dotted(name.rstrip(".")) for name in PREFIXED.findall(text)]
    for text in comments:
        failures += [check_path(p, t) for p, t in PATH.findall(text)]
        failures += [check_dotted(name.rstrip(".")) for name in PREFIXED.findall(text)]
    return [f for f in failures if f]


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_every_path_and_reference_of_a_page_exists(page: Path) -> None:
    assert page_failures(page.read_text(encoding="utf-8")) == []


@pytest.mark.parametrize("module", MODULES, ids=[str(p.relative_to(ROOT)) for p in MODULES])
def test_every_path_and_reference_of_a_docstring_exists(module: Path) -> None:
    assert source_failures(module) == []


def test_the_checker_tells_stale_references_from_good_ones() -> None:
    """What the two tests above rely on: a removed attribute, module or test is caught;
    a config key, a library call, a placeholder or a written output is not a reference."""
    assert check_dotted("FusedStepper.kicks") == "FusedStepper.kicks"
    assert check_dotted("pde_rotor.model.onsets.Wall") == "pde_rotor.model.onsets.Wall"
    assert check_dotted("motion.rotor_torques") == "motion.rotor_torques"
    assert check_dotted("publish", "pde_rotor.gallery.runner", role=True) == "publish"
    for good in ("pde_rotor.theory.dish.dish_hopf_onset", "FusedStepper.normals", "Run.stop_seed"):
        assert check_dotted(good) is None, good
    assert check_dotted(".restart.draw_stop", "pde_rotor.sweep.estimators", role=True) is None
    for other in ("grid.dx", "config.noise.sigma", "np.sqrt", "movie.mp4.part", "scheme"):
        assert check_dotted(other) is None, other
    assert check_path("tests/test_gpu.py", "") == "tests/test_gpu.py"
    assert check_path("tests/theory/test_dish.py", "::test_walls_push_and_pull") is None
    assert (
        check_path("tests/theory/test_dish.py", "::test_gone")
        == "tests/theory/test_dish.py::test_gone"
    )
    for written in ("gallery/output/convergence.csv", "data/sweeps/calibration", "data/NAME.nc"):
        assert check_path(written, "") is None, written
    assert check_path("data/sweeps/no_such_sweep", "") == "data/sweeps/no_such_sweep"
