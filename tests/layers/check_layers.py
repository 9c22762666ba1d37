#!/usr/bin/env python3
"""The layers are true: every #include "folder/file" in src/, io/, sweep/ and
apps/ names a folder that cmake/layers.txt lets the including folder use, and
README.md's Layout table ("may use") names the same folders as layers.txt.

    check_layers.py REPO_ROOT        (ctest layers.includes)

Prints one line per violation (file:line, the include, the rule) and exits 1;
exits 0 when everything agrees. tests/ and bench/ are not checked.
"""
import re
import sys
from pathlib import Path

INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')


def read_table(path):
    """{folder: set of folders it may use}, in the file's order."""
    table = {}
    for line in path.read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        folder, *uses = line.split()
        table[folder] = {u for u in uses if u != "-"}
    return table


def source_folders(root):
    """(folder, directory) of every checked folder: src/<folder>, io, sweep, apps."""
    for d in sorted((root / "src").iterdir()):
        if d.is_dir():
            yield d.name, d
    for name in ("io", "sweep", "apps"):
        yield name, root / name


def check_includes(root, table):
    errors = []
    folders = dict(source_folders(root))
    for folder, directory in folders.items():
        if folder not in table:
            errors.append(f"{directory.relative_to(root)}: folder has no row in cmake/layers.txt")
            continue
        for f in sorted(directory.rglob("*")):
            if f.suffix not in (".hpp", ".cpp", ".h", ".cc"):
                continue
            for n, line in enumerate(f.read_text(errors="replace").splitlines(), 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                inc = m.group(1)
                if "/" not in inc or (f.parent / inc).exists() and inc.split("/")[0] not in folders:
                    continue  # beside the including file ("commands.hpp", "candidates/candidate.hpp")
                target = inc.split("/")[0]
                if target == folder:
                    continue
                where = f"{f.relative_to(root)}:{n}"
                if target not in folders:
                    errors.append(f'{where}: #include "{inc}": no folder "{target}" in src/, io/, sweep/, apps/')
                elif target not in table[folder]:
                    allowed = " ".join(sorted(table[folder])) or "nothing"
                    errors.append(f'{where}: #include "{inc}": {folder} may not use {target} '
                                  f"(cmake/layers.txt: {folder} may use {allowed})")
    return errors


def check_readme(root, table):
    """README.md's Layout rows for the table's folders name exactly their folders."""
    errors = []
    seen = set()
    for line in (root / "README.md").read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 3 or not cells[0].startswith("`"):
            continue
        path = re.match(r"`([^`]+)`", cells[0]).group(1).rstrip("/")
        folder = path[len("src/"):] if path.startswith("src/") else path
        if folder not in table:
            continue
        seen.add(folder)
        named = {w for w in re.findall(r"[A-Za-z][\w+-]*", cells[2]) if w in table}
        if named != table[folder]:
            errors.append(f"README.md Layout, {path}: may use {' '.join(sorted(named)) or 'nothing'}; "
                          f"cmake/layers.txt says {' '.join(sorted(table[folder])) or 'nothing'}")
    for folder in table:
        if folder not in seen:
            errors.append(f"README.md Layout: no row for {folder} (cmake/layers.txt has one)")
    return errors


def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    table = read_table(root / "cmake" / "layers.txt")
    errors = check_includes(root, table) + check_readme(root, table)
    for e in errors:
        print(e)
    if errors:
        print(f"{len(errors)} layering violation(s)")
        return 1
    print(f"layers ok: {len(table)} folders, includes and README.md agree with cmake/layers.txt")
    return 0


if __name__ == "__main__":
    sys.exit(main())
