#!/usr/bin/python3
"""Fails if a function in the C++ sources is longer than the limit (issue 17: 150 lines).

    /usr/bin/python3 tests/layers/check_function_length.py ROOT [--limit 150] [--top N] [--dirs src,io,...]

Measures every function body in ROOT/<dir>/**/*.{cpp,hpp} for the given folders (default
src, io, sweep, apps): a brace block
opened directly inside a namespace, class, struct or at file scope whose opening is
preceded by a parameter list ")" (free functions, member functions, constructors; lambdas
and nested blocks count towards the function that holds them). The length is the number of
lines from the line of the opening brace to the line of the closing one, inclusive.
Strings, character literals and comments are skipped when matching braces.
"""
import argparse
import pathlib
import re
import sys

SCOPE_KEYWORDS = re.compile(r"\b(namespace|class|struct|union|enum)\b[^()]*$")


def strip_code(text):
    """The text with comments, strings and character literals blanked (newlines kept)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            j = min(n, j + 1)
            out.append(c + " " * (j - i - 2) + c if j - i >= 2 else text[i:j])
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(path):
    code = strip_code(path.read_text())
    stack = []  # (kind, line, header)
    found = []
    line = 1
    last_stmt = 0  # index just after the last ; { or }
    for i, c in enumerate(code):
        if c == "\n":
            line += 1
        elif c == "{":
            header = code[last_stmt:i]
            flat = " ".join(header.split())
            in_scope = all(k == "scope" for k, _, _ in stack)
            if SCOPE_KEYWORDS.search(flat) and "(" not in flat.split("=")[0][-1:]:
                kind = "scope"
            elif in_scope and flat.rstrip().endswith((")", "const", "override", "noexcept", "final")) or (
                    in_scope and re.search(r"\)\s*(const\s*)?(noexcept\s*)?(override\s*)?(->\s*[\w:<>,\s*&]+)?$", flat)):
                kind = "function"
            elif in_scope and re.search(r"\)\s*:\s*.*$", flat):  # constructor with an init list
                kind = "function"
            else:
                kind = "block"
            stack.append((kind, line, flat))
            last_stmt = i + 1
        elif c == "}":
            if stack:
                kind, start, header = stack.pop()
                if kind == "function":
                    name = re.findall(r"([\w:~<>]+)\s*\(", header)
                    found.append((line - start + 1, str(path), start, name[-1] if name else header[:60]))
            last_stmt = i + 1
        elif c == ";":
            last_stmt = i + 1
    return found


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("root")
    ap.add_argument("--limit", type=int, default=150)
    ap.add_argument("--top", type=int, default=5, help="also print the N longest functions")
    ap.add_argument("--dirs", default="src,io,sweep,apps", help="comma-separated folders under ROOT")
    a = ap.parse_args(argv)
    root = pathlib.Path(a.root)
    allf = []
    for d in a.dirs.split(","):
        for p in sorted((root / d).rglob("*")):
            if p.suffix in (".cpp", ".hpp"):
                allf += functions(p)
    allf.sort(reverse=True)
    for n, f, l, name in allf[: a.top]:
        print(f"{n:5d} lines  {pathlib.Path(f).relative_to(root)}:{l}  {name}")
    bad = [x for x in allf if x[0] > a.limit]
    print(f"{len(allf)} functions measured; {len(bad)} longer than {a.limit} lines")
    for n, f, l, name in bad:
        print(f"too long: {pathlib.Path(f).relative_to(root)}:{l} {name}: {n} lines", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
