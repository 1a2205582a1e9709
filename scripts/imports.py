#!/usr/bin/env python3
"""The module graph of src/, read from the code's own paths, and its cycles.

Usage: scripts/imports.py [--graph] [--root src] [--crate particle_lab]

A node is a module file (`src/physics/world.rs`, `src/physics/solver/soft/mod.rs`).
There is an edge A -> B when A's code (comments and string literals left out) names a
path into B: `use crate::physics::forces::Force`, `super::particles::AWAKE`,
`crate::physics::solver::soft::NONE` in an expression, a `pub use` re-export (also
one relative to a child, `pub use fields::Gravity;` in a `mod.rs`). A path
is followed as deep as it names module files, so `crate::physics::Force` (the facade's
re-export) is an edge to `physics/mod.rs`, and `super::Softness` from a file of
`solver/` is an edge to `solver/mod.rs`. Declaring a child (`mod step;`) is no edge:
it does not make the parent depend on what the child holds.
A path written inside an inline module (`mod tests { use super::keep_where; }`) is
read from that module, so its `super` is the file itself, not the file's parent.

Prints every cycle (one line per strongly connected component of more than one file,
its files in order, and one cycle through them) and exits 1 if there is any, else 0.
With --graph it also prints each file's imports, which is the layering to read.
"""

import argparse
import re
import sys
from pathlib import Path

PATH = re.compile(r"\b(crate|super|self)((?:::[A-Za-z_][A-Za-z0-9_]*)+)")
USE_GROUP = re.compile(r"\buse\s+(crate|super|self)((?:::[A-Za-z_][A-Za-z0-9_]*)*)::\{")
# A `use` whose path starts at a child module (`pub use fields::Gravity;` in a mod.rs).
RELATIVE_USE = re.compile(r"\buse\s+([A-Za-z_][A-Za-z0-9_]*)((?:::[A-Za-z_][A-Za-z0-9_]*)*)")


def strip_comments_and_strings(text):
    """The code without comments, string and char literals (kept as blanks)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    i += 1
        elif c == "r" and re.match(r'r#*"', text[i:]) and (i == 0 or not text[i - 1].isalnum()):
            hashes = re.match(r'r(#*)"', text[i:]).group(1)
            end = text.find('"' + hashes, i + 2 + len(hashes))
            i = n if end < 0 else end + 1 + len(hashes)
            out.append('""')
        elif c == '"':
            i += 1
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            i += 1
            out.append('""')
        elif c == "'" and re.match(r"'(\\.|[^\\'])'", text[i:]):
            i += len(re.match(r"'(\\.|[^\\'])'", text[i:]).group(0))
            out.append("' '")
        else:
            out.append(c)
            i += 1
    return "".join(out)


INLINE_MOD = re.compile(r"\bmod\s+([A-Za-z_][A-Za-z0-9_]*)\s*\{")


def inline_modules(code):
    """Each inline module of a file's code (`mod tests { ... }`): its name, and where its
    body starts and ends. A path inside one is relative to it, not to the file."""
    out = []
    for m in INLINE_MOD.finditer(code):
        depth, j = 1, m.end()
        while j < len(code) and depth:
            depth += {"{": 1, "}": -1}.get(code[j], 0)
            j += 1
        out.append((m.group(1), m.end(), j))
    return out


def module_of(path, root):
    """The module path of a file: src/physics/solver/soft/mod.rs -> [physics, solver, soft]."""
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "mod" or (len(parts) == 1 and parts[0] in ("lib", "main")):
        parts = parts[:-1]
    return parts


def build_graph(root):
    files = sorted(p for p in root.rglob("*.rs"))
    by_module = {}
    for f in files:
        module = tuple(module_of(f, root))
        # lib.rs is the crate root; main.rs is a separate crate that uses the library.
        if f.name == "main.rs" and f.parent == root:
            continue
        by_module[module] = f

    def resolve(base, segments):
        """The deepest module file that `base` + `segments` names, or None."""
        module = list(base)
        found = None
        for seg in segments:
            if seg == "super":
                module = module[:-1]
                found = by_module.get(tuple(module))
                continue
            if seg == "self":
                found = by_module.get(tuple(module))
                continue
            if tuple(module + [seg]) in by_module:
                module.append(seg)
                found = by_module[tuple(module)]
            else:
                break
        return found

    graph = {f: set() for f in by_module.values()}
    for module, f in by_module.items():
        code = strip_comments_and_strings(f.read_text())
        inline = inline_modules(code)

        def base_at(pos):
            """The module a path at `pos` is written in: the file's, or an inline
            `mod tests { ... }` inside it, where `super` is the file's own module."""
            return list(module) + [name for name, start, end in inline if start <= pos < end]

        # Paths inside `use a::b::{c::d, e}` groups: prefix each item with the group's base.
        # Each text is kept with where it stands in the file.
        expanded = [(code, None)]
        for m in RELATIVE_USE.finditer(code):
            if m.group(1) not in ("crate", "super", "self") and tuple(base_at(m.start())) + (m.group(1),) in by_module:
                expanded.append((f" self::{m.group(1)}{m.group(2)} ", m.start()))
        for m in USE_GROUP.finditer(code):
            start, depth, j = m.end(), 1, m.end()
            while j < len(code) and depth:
                depth += {"{": 1, "}": -1}.get(code[j], 0)
                j += 1
            base = m.group(1) + m.group(2)
            for item in re.split(r"[,\s]+", re.sub(r"[{}]", " ", code[start : j - 1])):
                if item and item not in ("self", "*") and re.match(r"[A-Za-z_]", item):
                    expanded.append((f" {base}::{item} ", m.start()))
                elif item == "self":
                    expanded.append((f" {base} ", m.start()))
        for text, at in expanded:
            for m in PATH.finditer(text):
                head, rest = m.group(1), m.group(2).split("::")[1:]
                written_in = base_at(m.start() if at is None else at)
                if head == "crate":
                    base, segments = [], rest
                elif head == "super":
                    base, segments = written_in, ["super"] + rest
                else:
                    base, segments = written_in, ["self"] + rest
                target = resolve(base, segments)
                if target is not None and target != f:
                    graph[f].add(target)
    return graph


def strongly_connected(graph):
    """Tarjan's components, each a sorted list of files."""
    index, low, stack, on_stack, out = {}, {}, [], set(), []
    counter = [0]
    sys.setrecursionlimit(10000)

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            out.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def one_cycle(graph, component):
    """A cycle through the component's first file, by breadth-first search."""
    members, start = set(component), component[0]
    previous, frontier = {start: None}, [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(graph[v]):
                if w == start:
                    path = [v]
                    while previous[path[-1]] is not None:
                        path.append(previous[path[-1]])
                    return list(reversed(path)) + [start]
                if w in members and w not in previous:
                    previous[w] = v
                    nxt.append(w)
        frontier = nxt
    return component


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=str(Path(__file__).resolve().parent.parent / "src"))
    parser.add_argument("--graph", action="store_true", help="print each file's imports too")
    args = parser.parse_args()
    root = Path(args.root)
    graph = build_graph(root)
    name = lambda f: str(f.relative_to(root))
    if args.graph:
        for f in sorted(graph):
            print(f"{name(f)} -> {', '.join(sorted(name(t) for t in graph[f])) or '(nothing)'}")
        print()
    cycles = [c for c in strongly_connected(graph) if len(c) > 1]
    if not cycles:
        print(f"no import cycle among {len(graph)} files under {root}")
        return 0
    for component in cycles:
        print(f"cycle among {len(component)} files: {', '.join(name(f) for f in component)}")
        print("  for example: " + " -> ".join(name(f) for f in one_cycle(graph, component)))
    return 1


if __name__ == "__main__":
    sys.exit(main())
