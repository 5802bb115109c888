#!/usr/bin/env python3
"""The line counts of docs/porting-from-ascent.md, "Lines before and after", are those of its
side-by-side adaptors.

    check_porting.py docs/porting-from-ascent.md

Each adaptor is the fenced block that starts with its own comment line (C `/* The Ascent
adaptor */`, Fortran `! The Tessera adaptor`, ...); the Python Tessera adaptor is the part of
its program between `# ---- the Tessera adaptor ----` and `# ---- the simulation's loop ----`;
the renders are the YAML blocks holding `action: "add_scenes"` and `viz.yaml`'s. A line counts
unless it is blank or holds only a comment. Prints the counts; exits 1 if the table differs.
"""
import re
import sys


def fenced(text):
    """(language, body) of every fenced block."""
    return re.findall(r"^```([A-Za-z0-9_+-]*)\n(.*?)^```\s*$", text, re.M | re.S)


def count(body, comment):
    n = 0
    for line in body.splitlines():
        s = line.strip()
        if not s or s.startswith(comment):
            continue
        n += 1
    return n


def main():
    text = open(sys.argv[1], encoding="utf-8").read()
    blocks = fenced(text)

    def first(lang, start):
        hits = [b for l, b in blocks if l == lang and b.lstrip().startswith(start)]
        if len(hits) != 1:
            sys.exit(f"{sys.argv[1]}: expected one ```{lang} block starting with {start!r}, found {len(hits)}")
        return hits[0]

    def holding(lang, needle):
        hits = [b for l, b in blocks if l == lang and needle in b]
        if not hits:
            sys.exit(f"{sys.argv[1]}: no ```{lang} block holds {needle!r}")
        return hits[0]

    tessera_py = holding("python", "# ---- the Tessera adaptor ----")
    tessera_py = tessera_py.split("# ---- the Tessera adaptor ----", 1)[1].split("# ---- the simulation's loop ----")[0]
    yaml_tessera = re.search(r"<!-- file: viz.yaml -->\s*```yaml\n(.*?)^```", text, re.M | re.S).group(1)
    found = {
        "C adaptor": (count(first("c", "/* The Ascent adaptor */"), "/*"),
                      count(first("c", "/* The Tessera adaptor */"), "/*")),
        "Fortran adaptor": (count(first("fortran", "! The Ascent adaptor"), "!"),
                            count(first("fortran", "! The Tessera adaptor"), "!")),
        "Python adaptor": (count(holding("python", "import ascent"), "#"), count(tessera_py, "#")),
        "renders": (count(holding("yaml", 'action: "add_scenes"'), "#"), count(yaml_tessera, "#")),
    }
    failed = False
    for row, (ascent, tessera) in found.items():
        m = re.search(r"^\| " + re.escape(row) + r"[^|]*\| (\d+) \| (\d+) \|$", text, re.M)
        stated = (int(m.group(1)), int(m.group(2))) if m else None
        ok = stated == (ascent, tessera)
        failed |= not ok
        print(f"{'ok  ' if ok else 'FAIL'} {row}: Ascent {ascent}, Tessera {tessera} lines; the table says "
              f"{stated if stated else 'nothing'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
