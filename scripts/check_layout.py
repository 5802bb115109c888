#!/usr/bin/env python3
"""The source layout stays by concept (README.md, "What is where"; ctest -L layout).

Usage: check_layout.py [--max-top N:DIR] REPO DIR...

For each DIR (a private include directory such as core/src, relative to REPO), every
`#include "..."` of every file under it is resolved as the compiler does (the including
file's folder first, then DIR) and read as an arrow from the file's folder to the included
file's folder (DIR's top is the folder "."). Fails when the arrows between the folders of one
DIR form a cycle (two folders that include each other both ways, or a longer loop), naming
one include of each arrow of the cycle. --max-top N:DIR also fails when DIR's top holds more
than N files (core/src: a room per concept, a few loose files at most).
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
SOURCE_EXT = (".h", ".hpp", ".cpp", ".cc", ".c")


def folder_arrows(root):
    """{(from_folder, to_folder): 'file: #include "x"'} for one include directory."""
    arrows = {}
    for dirpath, _dirs, files in os.walk(root):
        for name in sorted(files):
            if not name.endswith(SOURCE_EXT):
                continue
            path = os.path.join(dirpath, name)
            here = os.path.relpath(dirpath, root)
            with open(path, encoding="utf-8", errors="replace") as f:
                text = f.read()
            for inc in INCLUDE.findall(text):
                target = None
                for base in (dirpath, root):
                    cand = os.path.normpath(os.path.join(base, inc))
                    if os.path.isfile(cand):
                        target = cand
                        break
                if target is None:
                    continue  # not under this directory (another library's, or a test's)
                rel = os.path.relpath(target, root)
                if rel.startswith(".."):
                    continue
                there = os.path.dirname(rel) or "."
                if there != here:
                    arrows.setdefault((here, there), f'{os.path.relpath(path, root)}: #include "{inc}"')
    return arrows


def find_cycle(arrows):
    """One cycle of folders as a list [a, b, ..., a], or None."""
    graph = {}
    for a, b in arrows:
        graph.setdefault(a, []).append(b)
    state = {}  # 1 = on the current path, 2 = done
    stack = []

    def visit(n):
        state[n] = 1
        stack.append(n)
        for m in sorted(graph.get(n, [])):
            if state.get(m) == 1:
                return stack[stack.index(m):] + [m]
            if m not in state:
                found = visit(m)
                if found:
                    return found
        stack.pop()
        state[n] = 2
        return None

    for n in sorted(graph):
        if n not in state:
            found = visit(n)
            if found:
                return found
    return None


def main(argv):
    max_top = {}
    args = []
    i = 1
    while i < len(argv):
        if argv[i] == "--max-top":
            n, _, d = argv[i + 1].partition(":")
            max_top[d] = int(n)
            i += 2
        else:
            args.append(argv[i])
            i += 1
    if len(args) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    repo, dirs = args[0], args[1:]
    failures = 0
    for d in dirs + [d for d in max_top if d not in dirs]:
        root = os.path.join(repo, d)
        if not os.path.isdir(root):
            print(f"check_layout: {d}: no such directory")
            failures += 1
            continue
        if d in max_top:
            top = sorted(f for f in os.listdir(root) if os.path.isfile(os.path.join(root, f)))
            if len(top) > max_top[d]:
                print(f"check_layout: {d} holds {len(top)} files at its top (at most {max_top[d]}): "
                      f"{' '.join(top)}; put each in the folder of its concept")
                failures += 1
        if d not in dirs:
            continue
        arrows = folder_arrows(root)
        cycle = find_cycle(arrows)
        if cycle:
            print(f"check_layout: {d}: folders include each other: {' -> '.join(cycle)}")
            for a, b in zip(cycle, cycle[1:]):
                print(f"  {a} -> {b}: {d}/{arrows[(a, b)]}")
            failures += 1
        else:
            folders = sorted({f for arrow in arrows for f in arrow})
            print(f"check_layout: {d}: {len(arrows)} arrows between {len(folders)} folders, no cycle")
    print(f"check_layout: {len(dirs)} directories checked, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
