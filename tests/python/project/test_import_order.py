"""Imports run one way: neither the Rust core's modules (`crate::` paths) nor the Python
package's (imports at any depth, function-local ones included) form a cycle, and no module
of the package imports its root `dzhanibekov/__init__.py`."""

import ast
import re
from pathlib import Path

import dzhanibekov

RUST = Path(__file__).resolve().parents[3] / "rust"
PACKAGE = Path(dzhanibekov.__file__).resolve().parent


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """A cycle of `graph` as a list of nodes (first repeated last), or None."""
    state: dict[str, int] = {}  # 1 on the path, 2 done
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            if nxt not in state and (found := visit(nxt)):
                return found
        path.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state and (found := visit(node)):
            return found
    return None


def test_find_cycle_finds_one_and_only_one():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": set()}) is None
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]


# -- Rust -------------------------------------------------------------------------------------

def rust_modules() -> dict[str, Path]:
    """Module path (`run::registry`, `run` for run/mod.rs) -> file."""
    modules = {}
    for f in RUST.rglob("*.rs"):
        parts = list(f.relative_to(RUST).with_suffix("").parts)
        if parts[-1] == "mod":
            parts.pop()
        if parts == ["lib"]:
            continue
        modules["::".join(parts)] = f
    return modules


def _code(text: str) -> str:
    """`text` without comments (doc links name modules without using them) and strings."""
    # one pass, so a `//` inside a string ("https://…") is not taken for a comment
    text = re.sub(r'//[^\n]*|"(?:[^"\\]|\\.)*"|\'(?:[^\'\\]|\\.)\'',
                  lambda m: "" if m.group().startswith("//") else '""', text, flags=re.S)
    return re.sub(r"#\[cfg\(test\)\]\s*mod \w+\s*\{.*", "", text, flags=re.S)  # tests last


def _expand(prefix: str, body: str) -> list[str]:
    """The paths of `use prefix::{body}` (nested braces included)."""
    paths, depth, item = [], 0, ""
    for ch in body + ",":
        if ch == "," and depth == 0:
            item = item.strip()
            if item:
                m = re.match(r"([\w:]*?)::\{(.*)\}$", item, flags=re.S)
                if m:
                    paths += _expand(f"{prefix}::{m.group(1)}", m.group(2))
                else:
                    paths.append(f"{prefix}::{item}")
            item = ""
            continue
        depth += ch == "{"
        depth -= ch == "}"
        item += ch
    return paths


def crate_paths(text: str) -> list[str]:
    """Every `crate::...` path in the code of a file, `use` groups expanded."""
    code = _code(text)
    paths = []
    for m in re.finditer(r"crate::((?:\w+::)*)\{", code):
        depth, i = 1, m.end()
        while depth:
            depth += {"{": 1, "}": -1}.get(code[i], 0)
            i += 1
        paths += _expand("crate::" + m.group(1).rstrip(":"), code[m.end():i - 1])
    paths += re.findall(r"crate::(?:\w+::)*\w+(?!\w|::)", code)
    return [p.replace("crate::", "", 1) for p in paths]


def rust_graph(level: str) -> dict[str, set[str]]:
    """Edges between modules ("module") or top-level modules, the folders ("folder"). A
    folder's mod.rs that re-exports its children (`pub use child::X`) uses them."""
    modules = rust_modules()
    graph: dict[str, set[str]] = {}
    for name, f in modules.items():
        text = f.read_text()
        paths = crate_paths(text)
        if f.name == "mod.rs":
            paths += [f"{name}::{child}" for child in
                      re.findall(r"^\s*(?:pub(?:\(crate\))?\s+)?use\s+(\w+)::", _code(text), flags=re.M)
                      if f"{name}::{child}" in modules]
        src = name if level == "module" else name.split("::")[0]
        for path in paths:
            parts = path.split("::")
            target = next(("::".join(parts[:k]) for k in range(len(parts), 0, -1)
                           if "::".join(parts[:k]) in modules), None)
            if target is None:
                continue  # a re-export at the crate root (`crate::Error`)
            dst = target if level == "module" else target.split("::")[0]
            if dst != src:
                graph.setdefault(src, set()).add(dst)
    return graph


def test_the_rust_folders_import_one_way():
    graph = rust_graph("folder")
    assert {"run", "ensemble", "integrators", "rigid"} <= set(graph)
    assert find_cycle(graph) is None, find_cycle(graph)


def test_the_rust_modules_import_one_way():
    graph = rust_graph("module")
    assert "run::grid" in graph["run::registry"]
    assert find_cycle(graph) is None, find_cycle(graph)


def test_the_rust_walk_reads_past_slashes_and_quotes_in_strings():
    text = 'let u = "https://x \\\n y"; let c = \'"\'; crate::pool::install(|| ());\n'
    assert crate_paths(text) == ["pool::install"]


def test_the_rust_walk_sees_uses_in_groups():
    text = "use crate::run::{grid::FrameGrid, registry::{Method, METHODS}};\n// crate::python\n"
    assert sorted(crate_paths(text)) == ["run::grid::FrameGrid", "run::registry::METHODS",
                                         "run::registry::Method"]


# -- Python -----------------------------------------------------------------------------------

def python_modules() -> dict[str, Path]:
    modules = {}
    for f in PACKAGE.rglob("*.py"):
        parts = ["dzhanibekov", *f.relative_to(PACKAGE).with_suffix("").parts]
        if parts[-1] == "__init__":
            parts.pop()
        modules[".".join(parts)] = f
    for stub in PACKAGE.glob("*.pyi"):  # extension modules (the core): leaves
        modules.setdefault(f"dzhanibekov.{stub.stem}", stub)
    return modules


def python_imports(name: str, f: Path, modules: dict[str, Path]) -> set[str]:
    """The package's modules `name` imports, at any depth of its code."""
    package = name if f.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(f.read_text())):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = package
            for _ in range(node.level - 1):
                base = base.rpartition(".")[0]
            base = (f"{base}.{node.module}" if node.module else base) if node.level else node.module
            # `from pkg import sub` imports the submodule sub
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base
                       for a in node.names]
        else:
            continue
        found |= {t for t in targets if t and t.split(".")[0] == "dzhanibekov"}
    return found


def python_graph() -> dict[str, set[str]]:
    modules = python_modules()
    return {name: python_imports(name, f, modules) - {name} for name, f in modules.items()
            if f.suffix == ".py"}


def test_the_python_modules_import_one_way():
    graph = python_graph()
    assert "dzhanibekov.rows" in graph["dzhanibekov.simulate"]
    assert find_cycle(graph) is None, find_cycle(graph)


def test_no_module_imports_the_package_root():
    offenders = [name for name, dsts in python_graph().items()
                 if "dzhanibekov" in dsts and name != "dzhanibekov"]
    assert not offenders, offenders


def test_the_python_walk_sees_function_local_imports(tmp_path):
    f = tmp_path / "m.py"
    f.write_text("def g():\n    from .simulate import simulate\n    from . import _core\n")
    modules = {"dzhanibekov.simulate": f, "dzhanibekov._core": f}
    assert python_imports("dzhanibekov.x", f, modules) == {"dzhanibekov.simulate",
                                                            "dzhanibekov._core"}


def declared_layers() -> list[set[str]]:
    """The layers rust/lib.rs declares ("… → …"), first the ones that use nothing."""
    doc = " ".join(line.removeprefix("//!").strip() for line in
                   (RUST / "lib.rs").read_text().splitlines() if line.startswith("//!"))
    order = doc[doc.index("The modules in layers"):].split(":", 1)[1].split(".")[0]
    return [set(re.findall(r"`(\w+)`", layer)) for layer in order.split("→")]


def test_the_rust_folders_follow_the_layers_lib_rs_declares():
    layers = declared_layers()
    level = {name: k for k, layer in enumerate(layers) for name in layer}
    graph = rust_graph("folder")
    assert set(level) == {name.split("::")[0] for name in rust_modules()}  # every folder placed
    upward = [(src, dst) for src, dsts in graph.items() for dst in dsts
              if level[dst] >= level[src]]
    assert not upward, f"uses of a module in the same or a later layer: {sorted(upward)}"
