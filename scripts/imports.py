#!/usr/bin/env python3
"""Checks that glint's imports run one way: no cycle between the top-level
modules of src/, nor between the files of one module.

An edge A -> B is a `use`, or a path, naming `crate::B...` (between
modules) or `super::X` / `crate::m::X` (between files of module m, X
resolved through the `pub use` re-exports of m's mod.rs to the file that
defines it). `mod x;` declarations are not edges; test modules
(`#[cfg(test)] mod tests`, src/tests/) are left out. Prints the module
graph; exits 1 on a cycle. With --dot, prints the module graph as
Graphviz instead (`scripts/imports.py --dot | tred | dot -Tpng -o
docs/architecture.png` draws the map in docs/architecture.md, each
arrow implied by two others left out).
"""
import re
import sys
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "src"


def code(path):
    text = path.read_text()
    cut = re.search(r"#\[cfg\(test\)\]\s*mod tests\b", text)
    if cut:
        text = text[: cut.start()]
    text = re.sub(r"//[^\n]*", "", text)  # comments, doc comments included
    return text


def top_module(path):
    rel = path.relative_to(SRC)
    if rel.parts[0] == "bin":
        return "bin"
    return rel.parts[0].removesuffix(".rs")


def cycles(graph):
    """Every cycle found by a depth-first search, as node lists."""
    found, state, stack = [], {}, []

    def visit(n):
        state[n] = 1
        stack.append(n)
        for m in sorted(graph.get(n, ())):
            if state.get(m) == 1:
                found.append(stack[stack.index(m):] + [m])
            elif m not in state:
                visit(m)
        stack.pop()
        state[n] = 2

    for n in sorted(graph):
        if n not in state:
            visit(n)
    return found


files = [p for p in SRC.rglob("*.rs") if "tests" not in p.relative_to(SRC).parts]
tops = {top_module(p) for p in files} - {"lib", "bin"}

# Between modules.
graph = {}
for p in files:
    a = top_module(p)
    for b in re.findall(r"\bcrate::(\w+)", code(p)):
        if b in tops and b != a:
            graph.setdefault(a, set()).add(b)
        elif a == "bin" or a == "lib":
            pass
    if a == "bin":
        graph.setdefault(a, set()).update({"lib"})

bad = cycles(graph)

# Between the files of each folder module.
for folder in sorted({p.parent for p in files if p.name == "mod.rs"}):
    siblings = {p.stem: p for p in folder.glob("*.rs")}
    sub = {p.name: p / "mod.rs" for p in folder.iterdir() if (p / "mod.rs").exists()}
    names = {**siblings, **sub}
    # Names re-exported by mod.rs: name -> the file that defines it.
    mod_text = code(folder / "mod.rs")
    exported = {}
    for src_mod, items in re.findall(r"pub(?:\(crate\))?\s+use\s+(\w+)::\{?([\w\s,{}:]*)\}?;", mod_text):
        for item in re.findall(r"\w+", items):
            if src_mod in names:
                exported[item] = src_mod
    modpath = "::".join(folder.relative_to(SRC).parts)
    g = {}
    for name, p in names.items():
        t = code(p) if p.exists() else ""
        me = "mod" if p == folder / "mod.rs" else name
        refs = re.findall(r"\bsuper::(\w+)", t) if me != "mod" else []
        refs += re.findall(r"\bcrate::" + re.escape(modpath) + r"::(\w+)", t)
        # `use super::{a, b::c}` lists
        for group in re.findall(r"\bsuper::\{([^;]*)\}", t) if me != "mod" else []:
            refs += re.findall(r"(?<![:\w])(\w+)", group)
        if me == "mod":
            refs += [m for m in re.findall(r"^\s*(?:pub(?:\(crate\))?\s+)?use\s+(\w+)::", t, re.M)]
            refs += re.findall(r"\b(\w+)::\w+", t)
        for r in refs:
            target = r if r in names else exported.get(r, "mod" if r not in ("self", "super", "crate") else None)
            if target and target != me and (target in names or target == "mod"):
                g.setdefault(me, set()).add(target)
    for c in cycles(g):
        bad.append([f"{modpath}/{n}" for n in c])

if "--dot" in sys.argv[1:]:
    print("digraph glint {")
    print('  rankdir=LR; node [shape=box, fontname="Helvetica"];')
    # The command line reaches the library only through lib.rs: left out.
    for a in sorted(set(graph) - {"bin"}):
        for b in sorted(graph[a]):
            print(f'  "{a}" -> "{b}";')
    print("}")
    sys.exit(1 if bad else 0)
for a in sorted(graph):
    print(f"{a} -> {', '.join(sorted(graph[a]))}")
if bad:
    for c in bad:
        print("cycle: " + " -> ".join(c), file=sys.stderr)
    sys.exit(1)
print("no import cycle")
