#!/usr/bin/env python3
"""Lists import cycles between the source files of each workspace crate.

A file imports another when it names a path into it: `crate::a::b`, `super::x`,
`self::x`, or `child::x` for a module `child` the file declares (`mod child;`), in
`use` items (brace groups `use super::{a::b, c}` included) and inline paths alike; doc
comments and `#[cfg(test)]` modules are skipped, since tests may reach anywhere. A
module's `mod.rs` and its children count as distinct files; a parent declaring
`mod child;` is not an import.
Prints each cycle found and exits 1 if there is one, 0 otherwise.

    python3 scripts/import-cycles.py [CRATE_DIR ...]   # default: every crate with src/
"""
import os
import re
import sys

PATH = re.compile(r"(?<![$\w:])(crate|super|self)((?:::[A-Za-z_][A-Za-z0-9_]*)+)")
MOD = re.compile(r"^\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+([A-Za-z_][A-Za-z0-9_]*)\s*;")
USE = re.compile(r"\buse\s+([^;]*);", re.S)


def use_paths(tree):
    """The paths of a use tree: `a::{b::c, d as e, self}` -> a::b::c, a::d, a."""
    tree = re.sub(r"\s+", "", tree)
    tree = re.sub(r"\bas\b\w+", "", tree)
    depth, start = 0, None
    for i, c in enumerate(tree):
        if c == "{":
            if depth == 0:
                start = i
            depth += 1
        elif c == "}":
            depth -= 1
            if depth == 0:
                prefix = tree[:start]
                inner, rest = tree[start + 1 : i], tree[i + 1 :]
                out, parts, depth2, last = [], [], 0, 0
                for j, d in enumerate(inner):
                    if d == "{":
                        depth2 += 1
                    elif d == "}":
                        depth2 -= 1
                    elif d == "," and depth2 == 0:
                        parts.append(inner[last:j])
                        last = j + 1
                parts.append(inner[last:])
                for part in parts:
                    if not part:
                        continue
                    if part == "self":
                        out.append(prefix.rstrip(":"))
                    else:
                        out.extend(use_paths(prefix + part + rest))
                return out
    return [tree]


def modules(src):
    """Module path (tuple) -> file, for every .rs file under src."""
    out = {}
    for root, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs"):
                continue
            full = os.path.join(root, f)
            rel = os.path.relpath(full, src)[:-3].split(os.sep)
            # `mod.rs` names its folder's module; `lib.rs` and `main.rs` only at the root.
            if rel[-1] == "mod" or (len(rel) == 1 and rel[0] in ("lib", "main")):
                rel = rel[:-1]
            if rel and rel[0] == "bin":
                continue
            out[tuple(rel)] = full
    return out


def code_lines(path):
    """The file's lines outside comments and outside a trailing test module."""
    lines = []
    for line in open(path, encoding="utf-8"):
        s = line.strip()
        if s.startswith("#[cfg(test)]"):
            break
        if s.startswith("//"):
            continue
        lines.append(line.split("//")[0])
    return lines


def resolve(mods, here, kind, parts):
    base = {"crate": (), "super": here[:-1], "self": here}[kind]
    path = list(base) + parts
    # The longest prefix naming a module file.
    while path:
        if tuple(path) in mods:
            return tuple(path)
        path.pop()
    return None


def graph(src):
    mods = modules(src)
    edges = {m: set() for m in mods}
    for m, f in mods.items():
        # A mod.rs's `super` is its parent; a leaf file's `super` is its parent too.
        lines = code_lines(f)
        children = {mm.group(1) for line in lines for mm in [MOD.match(line)] if mm}
        child_path = (
            re.compile(r"(?<![$\w:])(" + "|".join(sorted(children)) + r")((?:::[A-Za-z_][A-Za-z0-9_]*)+)")
            if children
            else None
        )
        text = "".join(l for l in lines if not MOD.match(l))
        found = []
        for tree in USE.findall(text):
            for path in use_paths(tree):
                segs = [p for p in path.split("::") if p]
                if len(segs) >= 2 and segs[0] in ("crate", "super", "self"):
                    found.append((segs[0], "::" + "::".join(segs[1:])))
                elif len(segs) >= 1 and segs[0] in children:
                    found.append(("self", "::" + "::".join(segs)))
        found += PATH.findall(text)
        if child_path:
            found += [("self", "::" + c + rest) for c, rest in child_path.findall(text)]
        for kind, rest in found:
            parts = [p for p in rest.split("::") if p]
            if kind == "super":
                # `super::super::x`
                here = m
                while parts and parts[0] == "super":
                    here = here[:-1]
                    parts = parts[1:]
                t = resolve(mods, here, "super", parts)
            else:
                t = resolve(mods, m, kind, parts)
            if t is not None and t != m and not m[: len(t)] == t:
                edges[m].add(t)
    return edges


def cycles(edges):
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(comp)

    sys.setrecursionlimit(10000)
    for v in edges:
        if v not in index:
            visit(v)
    return out


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    crates = sys.argv[1:] or sorted(
        os.path.join(root, d) for d in os.listdir(root) if os.path.isdir(os.path.join(root, d, "src"))
    )
    found = False
    for c in crates:
        for comp in cycles(graph(os.path.join(c, "src"))):
            found = True
            names = sorted("::".join(m) or "(root)" for m in comp)
            print(f"{os.path.basename(os.path.normpath(c))}: {' <-> '.join(names)}")
    if not found:
        print("no import cycles")
    sys.exit(1 if found else 0)


if __name__ == "__main__":
    main()
