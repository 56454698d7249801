#!/usr/bin/env python3
"""Lists the C++ functions longer than a limit: every function body in the given folders, measured from
the first line of its declaration to its closing brace (lambdas count as part of the function that holds
them). Exit status 1 when one is over the limit, so ctest keeps the rule "no function over 150 lines".

  function_lengths.py [--limit N] [--top K] ROOT [FOLDER ...]
"""
import argparse
import pathlib
import re
import sys

SOURCE_SUFFIXES = {".cpp", ".hpp", ".h", ".cc"}
QUALIFIERS = re.compile(r"(\s|const|volatile|noexcept(\s*\([^()]*\))?|override|final|mutable|&|&&|"
                        r"->\s*[\w:<>,\s*&]+|requires\s+[^{}]+)*$")
CTOR_INIT = re.compile(r"\)\s*(noexcept\s*)?:(?!:)")


def blank(text):
    """The text with comments, string and character literals and preprocessor lines replaced by spaces,
    newlines kept, so offsets and line numbers stay those of the file."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#":
            # A preprocessor line, with its continuations.
            j = i
            while j < n and not (text[j] == "\n" and text[j - 1] != "\\"):
                j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            continue
        if c == "\n":
            line_start = True
            out.append(c)
            i += 1
            continue
        if not c.isspace():
            line_start = False
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
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^()\\\s]{0,16})\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i + m.end())
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                out.append(" ")  # a digit separator: 1'000'000
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(n, j + 1)
            out.append(" " * (j - i))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(text):
    """(first line, last line, name) of every function body at namespace or class scope."""
    code = blank(text)
    line_of = []
    line = 1
    for ch in code:
        line_of.append(line)
        if ch == "\n":
            line += 1
    scopes = []  # kinds of the open braces: "ns", "class", "fn", "other"
    stmt_start = 0
    found = []
    for i, ch in enumerate(code):
        in_fn = any(k in ("fn", "other") for k in scopes)
        if ch == "{":
            if in_fn:
                scopes.append("other")
                continue
            stmt = code[stmt_start:i].strip()
            if re.search(r"\bnamespace\b", stmt) or re.match(r'extern\s*$', stmt.replace('"C"', "").strip()):
                kind = "ns"
            elif CTOR_INIT.search(stmt) and re.search(r"[\w>]\s*$", stmt):
                kind = "other"  # a braced member initialiser: v_{1}
            elif (stmt.endswith(")") or stmt.endswith("}") or QUALIFIERS.fullmatch(stmt[stmt.rfind(")") + 1:] if ")" in stmt else "x")) \
                    and ")" in stmt and "=" not in stmt.split("(")[0]:
                kind = "fn"
            elif re.search(r"\b(class|struct|union|enum)\b", stmt):
                kind = "class"
            else:
                kind = "other"
            if kind == "fn":
                start = stmt_start + (len(code[stmt_start:i]) - len(code[stmt_start:i].lstrip()))
                name = re.findall(r"([~\w:]+|operator\S+)\s*\(", stmt)
                found.append([line_of[start], None, name[0] if name else "?", len(scopes)])
            scopes.append(kind)
            if kind in ("ns", "class"):
                stmt_start = i + 1
        elif ch == "}":
            if not scopes:
                continue
            kind = scopes.pop()
            if kind == "fn":
                for f in reversed(found):
                    if f[1] is None and f[3] == len(scopes):
                        f[1] = line_of[i]
                        break
            # A closed body or scope ends a statement; a braced initialiser does not (S() : v_{1} {).
            if kind != "other" and not any(k in ("fn", "other") for k in scopes):
                stmt_start = i + 1
        elif ch == ";" and not in_fn:
            stmt_start = i + 1
        elif ch == ":" and not in_fn and re.search(r"\b(public|private|protected)\s*$", code[stmt_start:i]):
            stmt_start = i + 1
    return [(a, b, name) for a, b, name, _ in found if b is not None]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--limit", type=int, default=150)
    ap.add_argument("--top", type=int, default=0, help="also print the K longest functions")
    ap.add_argument("root")
    ap.add_argument("folders", nargs="*", default=["driver", "mapper", "messages", "tools"])
    args = ap.parse_args()
    root = pathlib.Path(args.root)
    rows = []
    for folder in args.folders:
        for path in sorted((root / folder).rglob("*")):
            if path.suffix in SOURCE_SUFFIXES and path.is_file():
                for first, last, name in functions(path.read_text(errors="replace")):
                    rows.append((last - first + 1, f"{path.relative_to(root)}:{first}", name))
    rows.sort(reverse=True)
    for length, where, name in rows[: args.top]:
        print(f"{length:5d}  {where}  {name}")
    over = [r for r in rows if r[0] > args.limit]
    for length, where, name in over:
        print(f"function_lengths: {where}: {name} is {length} lines, over the limit of {args.limit}",
              file=sys.stderr)
    print(f"function_lengths: {len(rows)} functions in {', '.join(args.folders)}; "
          f"{len(over)} over {args.limit} lines")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
