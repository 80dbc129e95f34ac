#!/usr/bin/env python3
"""Lists the functions in host/ and shaders/ longer than N lines (default 80).

Brace matching over C++ and GLSL with comments, strings and preprocessor lines blanked: a
top-level brace (or one inside a namespace, struct or class) opens a function body when the
text before it holds a parameter list and is not a type, namespace or initializer. Length is
counted from the line of the function's name to its closing brace, like a reader would.
Usage: tests/code_checks/long_functions.py [--max N] [ROOT]   (exit status 1 when any function is longer)
"""
import argparse
import pathlib
import re
import sys

SUFFIXES = {".cpp", ".h", ".hpp", ".glsl", ".comp"}
SCOPES = re.compile(r"\b(namespace|struct|class|union|enum)\b[^()]*$|\bextern\s+\"C\"\s*$")


def blank(text):
    """Comments, string/char literals and preprocessor lines as spaces (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            j += 1
        elif c == "#" and not text[text.rfind("\n", 0, i) + 1:i].strip():
            j = i
            while j < n and (text[j] != "\n" or text[j - 1] == "\\"):
                j += 1
        else:
            out.append(c)
            i += 1
            continue
        out.append(re.sub(r"[^\n]", " ", text[i:j]))
        i = j
    return "".join(out)


def functions(text):
    """(name, first line, last line) of every function body."""
    code = blank(text)
    found, stack, head_start = [], [], 0  # stack: (kind, start offset, header)
    for i, c in enumerate(code):
        if c in ";":
            head_start = i + 1
        elif c == "{":
            header = code[head_start:i].strip()
            in_function = any(kind == "function" for kind, _, _ in stack)
            if in_function or stack and stack[-1][0] == "other":
                kind = "other"
            elif SCOPES.search(header):
                kind = "scope"
            elif "(" not in header or re.search(r"=\s*[\w:<>]*$", header):
                kind = "other"  # an initializer or a type's body
            else:
                kind = "function"
            stack.append((kind, head_start, header))
            head_start = i + 1
        elif c == "}":
            if stack:
                kind, start, header = stack.pop()
                if kind == "function":
                    name = re.findall(r"([~\w:]+)\s*\(", header)
                    first = code.count("\n", 0, start + len(code[start:i]) - len(code[start:i].lstrip())) + 1
                    found.append((name[0] if name else "?", first, code.count("\n", 0, i) + 1))
            head_start = i + 1
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=80)
    ap.add_argument("root", nargs="?", default=pathlib.Path(__file__).resolve().parents[2])
    args = ap.parse_args()
    root = pathlib.Path(args.root)
    long = []
    for folder in ("host", "shaders"):
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in SUFFIXES:
                continue
            for name, first, last in functions(path.read_text(errors="replace")):
                if last - first + 1 > args.max:
                    long.append((last - first + 1, f"{path.relative_to(root)}:{first}", name))
    for lines, where, name in sorted(long, reverse=True):
        print(f"{lines:5d}  {where}  {name}")
    return 1 if long else 0


if __name__ == "__main__":
    sys.exit(main())
