#!/usr/bin/env python3
"""Checks that the files comments and docs cite are in the source tree.

A clone of the project holds only its own files, so a comment that sends the reader to a document beside
the checkout (or to a file that was renamed) leaves the reader with nothing. This checker reads

- the comments of source files (C, C++, Java and LCM `//` and `/* */`; `#` comments of Python, shell,
  CMake, YAML and systemd files), and
- the text and link targets of Markdown files,

and reports every cited file that is not in the tree:

- any `NAME.md` (a bare name must be the name of some file in the tree; a path must resolve from the
  citing file's folder or from the root), and the sections cited right after it (`docs/filter.md §3.2`
  needs a heading numbered 3.2 in docs/filter.md);
- any path that starts with a top-level folder of the tree (`mapper/filter/src/kernel.cpp`), which must
  exist as written;
- any other path or bare name of a source file (`support/multicast.hpp`, `probit_update.hpp`), which must
  be the tail of a path in the tree, unless the words before it on the line name the other project it
  belongs to (`ros rawdata.h:75`, `vd packet_decoder.cpp:188`, `OctoMap's OcTree.h`);
- a Markdown link to a relative path, which must exist.

The change log is a record of releases: the files it names are the files of the release it describes,
renamed and removed ones included, so only its links are checked.

Data read at run time from beside the checkout (`../shared/data/...`), absolute paths, URLs and
placeholders (`FILE.yaml`, `a.cpp`) are not citations of documents and are left alone; `../shared/docs`
is a citation and is reported.

Usage: check_citations.py [--root DIR]   (exit status 1 and one line per problem when anything is missing)
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
from dataclasses import dataclass

C_LIKE = {".c", ".cc", ".cpp", ".h", ".hh", ".hpp", ".java", ".lcm"}
HASH_COMMENTS = {".py", ".sh", ".cmake", ".yaml", ".yml", ".service", ".conf", ".target"}
MARKDOWN = {".md"}
# Names files as they were when each change was made; see the module text.
CHANGE_LOG = "CHANGELOG.md"

# File kinds a citation can name. Source files (`.h` and `.cc` included, so that a citation of another
# project's file is recognised and attributed) are checked wherever they appear; data and configuration
# files (`sim.yaml`, `capture.pcap`) are mostly files a program reads or writes at run time, so they are
# checked only as paths from a top-level folder of the tree (`systemd/mapper.yaml`).
CODE_EXT = {"hpp", "cpp", "h", "hh", "cc", "c", "py", "sh", "cmake", "lcm", "java"}
DATA_EXT = {"yaml", "yml", "txt", "xml", "json", "service", "conf", "target", "html", "pcap"}
SOURCE_EXT = "(?:" + "|".join(sorted(CODE_EXT | DATA_EXT, key=len, reverse=True)) + ")"
TOKEN = re.compile(
    r"(?<![\w./@:-])"  # not inside a longer word, path or URL
    r"((?:\.\./|\./)*(?:[A-Za-z0-9_+-]+/)*[A-Za-z0-9_+-]+(?:\.[A-Za-z0-9_+-]+)*\.(?:md|" + SOURCE_EXT + r"))"
    r"(?![\w/-])"
)
SECTIONS = re.compile(r"^(?:\s*(?:,|and|or|/|to)?\s*§\s*(\d+(?:\.\d+)*))+")
SECTION_ONE = re.compile(r"§\s*(\d+(?:\.\d+)*)")
MARKDOWN_LINK = re.compile(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
HEADING = re.compile(r"^#{1,6}\s+(.*?)\s*#*\s*$")
HEADING_NUMBER = re.compile(r"^(\d+(?:\.\d+)*)\.?\s")
# A heading named right after a document: `docs/mapping.md, "Covariance storage"`.
QUOTED_HEADING = re.compile(r'^,?\s*"([^"]+)"')

# Words that attribute the file name after them to another project: the ROS velodyne driver (`ros`),
# velodyne_decoder (`vd`), VeloView, nebula, Autoware, libbot, OctoMap, GMapping, Cartographer, LCM. In a
# comment they count between the previous file name on the line (or the line before) and this one; in
# Markdown, within the sentence.
EXTERNAL = re.compile(
    r"\b(?:ros2?|ROS\s*2?|vd|velodyne_decoder|VeloView|LidarView|nebula|Autoware(?:\.Auto)?|libbot2?|bot2|"
    r"OctoMap|octomap|GMapping|gmapping|Cartographer|lcm-gen|LCM|Ouster|ouster|Hesai|PCL|ricoslam|"
    r"metricEvaluator|wavemap|rosbag2)\b"
)

# Placeholders that stand for any file in usage text and examples.
PLACEHOLDER = re.compile(
    r"^(?:FILE|DIR|NAME|PATH|OUT|IN|OUTPUT|INPUT|file|a|b|x|y|foo|bar|my-[\w-]+|your[\w-]*|example[\w-]*)"
    r"\.[\w.]+$"
)
# A name the text itself says is generated at build time ("preset_texts.cpp is generated into the build
# tree").
GENERATED_AFTER = re.compile(r"^\s*(?:is|are)?\s*generated\b")


@dataclass(frozen=True)
class Problem:
    path: str
    line: int
    message: str

    def __str__(self) -> str:
        return f"{self.path}:{self.line}: {self.message}"


def tracked_files(root: str) -> list[str]:
    """The tree's files, relative to root: in a checkout, those git tracks or does not ignore; else a walk."""
    try:
        out = subprocess.run(
            ["git", "-C", root, "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
            capture_output=True,
            check=True,
        )
        files = [f for f in out.stdout.decode().split("\0") if f]
        if files:
            return [f for f in files if os.path.exists(os.path.join(root, f))]
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for folder, dirs, names in os.walk(root):
        dirs[:] = [d for d in dirs if not d.startswith(".") and not d.startswith("build")]
        for name in names:
            files.append(os.path.relpath(os.path.join(folder, name), root))
    return files


def c_like_comments(text: str):
    """(line, comment text) for every // and /* */ comment, skipping string and character literals."""
    i, line, n = 0, 1, len(text)
    while i < n:
        ch = text[i]
        if ch == "\n":
            line += 1
            i += 1
        elif text.startswith("//", i):
            end = text.find("\n", i)
            end = n if end < 0 else end
            yield line, text[i + 2 : end]
            i = end
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end
            for k, part in enumerate(text[i + 2 : end].split("\n")):
                yield line + k, part
            line += text.count("\n", i, end)
            i = end + 2
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            open_paren = text.find("(", i + 2)
            delim = text[i + 2 : open_paren]
            end = text.find(")" + delim + '"', open_paren)
            end = n if end < 0 else end + len(delim) + 2
            line += text.count("\n", i, end)
            i = end
        elif ch in "\"'":
            j = i + 1
            while j < n and text[j] != ch and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            i = j + 1
        else:
            i += 1


def hash_comments(text: str):
    """(line, comment text) for every # comment: a # starting a line or after a blank, outside quotes."""
    for number, line in enumerate(text.split("\n"), start=1):
        quote = None
        for k, ch in enumerate(line):
            if quote:
                if ch == "\\":
                    continue
                if ch == quote:
                    quote = None
            elif ch in "\"'":
                quote = ch
            elif ch == "#" and (k == 0 or line[k - 1] in " \t"):
                yield number, line[k + 1 :]
                break


def markdown_lines(text: str):
    """Every line of a Markdown file but those of fenced code blocks (commands, not citations)."""
    fenced = False
    for number, line in enumerate(text.split("\n"), start=1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if not fenced:
            yield number, line


class Tree:
    def __init__(self, root: str):
        self.root = root
        self.files = set(tracked_files(root))
        self.basenames = {os.path.basename(f) for f in self.files}
        self.top = {f.split("/", 1)[0] for f in self.files if "/" in f}
        self._headings: dict[str, list[str]] = {}

    def exists(self, rel: str) -> bool:
        rel = os.path.normpath(rel)
        return rel in self.files or any(f.startswith(rel + "/") for f in self.files)

    def has_tail(self, tail: str) -> bool:
        return any(f == tail or f.endswith("/" + tail) for f in self.files) or (
            tail.startswith("ogf/") and self.generated_header(tail)
        )

    def generated_header(self, include: str) -> bool:
        """ogf/NAME_t.hpp is generated by lcm-gen from messages/lcmtypes/ogf_NAME_t.lcm."""
        name = os.path.basename(include)
        return name.endswith("_t.hpp") and f"messages/lcmtypes/ogf_{name[:-4]}.lcm" in self.files

    def headings(self, doc: str) -> list[str]:
        if doc not in self._headings:
            with open(os.path.join(self.root, doc), encoding="utf-8", errors="replace") as f:
                lines = markdown_lines(f.read())
                self._headings[doc] = [m.group(1) for _, line in lines if (m := HEADING.match(line))]
        return self._headings[doc]

    def sections(self, doc: str) -> set[str]:
        """The section numbers of a document's numbered headings (`## 3.2 Azimuth` gives 3.2)."""
        return {m.group(1) for h in self.headings(doc) if (m := HEADING_NUMBER.match(h))}

    def anchors(self, doc: str) -> set[str]:
        """The link anchors of a document's headings, as GitHub makes them."""
        return {slug(h) for h in self.headings(doc)}

    def resolve_doc(self, citing: str, token: str) -> str | None:
        """The tree file a .md citation names, or None."""
        if "/" not in token:
            if token in self.files:
                return token
            beside = os.path.normpath(os.path.join(os.path.dirname(citing), token))
            if beside in self.files:
                return beside
            matches = sorted(f for f in self.files if os.path.basename(f) == token)
            return matches[0] if matches else None
        for candidate in (os.path.join(os.path.dirname(citing), token), token):
            candidate = os.path.normpath(candidate)
            if candidate in self.files:
                return candidate
        return None


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation but `-` and `_` dropped, blanks made `-`."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def is_run_time_data(token: str) -> bool:
    return "shared/data/" in token or token.startswith("build/") or "/build/" in token


def check_text(tree: Tree, citing: str, number: int, text: str, problems: list[Problem], previous: str = "",
               sentence: bool = False) -> None:
    """Checks the citations in one line of comment or Markdown text. The words that may attribute a file name
    to another project are, in a comment, those since the previous file name on the line (or, for the first,
    the line before it too, passed as `previous`); in Markdown, with `sentence`, those since the start of the
    sentence (`previous` holds the paragraph's earlier lines)."""
    last_end = 0
    for m in TOKEN.finditer(text):
        token = m.group(1)
        if sentence:
            before = sentence_start(previous + " " + text[: m.start()])
        else:
            before = (previous if last_end == 0 else "") + " " + text[last_end : m.start()]
        last_end = m.end()
        ext = token.rsplit(".", 1)[1]
        first = token.split("/", 1)[0]
        from_top = "/" in token and first in tree.top
        if "shared/docs/" in token or (token.startswith("../shared/") and ext == "md"):
            problems.append(Problem(citing, number, f"cites {token}, which is beside the tree, not in it"))
            continue
        if is_run_time_data(token) or PLACEHOLDER.match(os.path.basename(token)) or token.startswith("../"):
            continue
        if ext == "md":
            check_document(tree, citing, number, token, before, text[m.end() :], problems)
            continue
        if from_top:
            if not tree.exists(token):
                problems.append(Problem(citing, number, f"cites {token}, which is not in the tree"))
            continue
        if ext in DATA_EXT or tree.has_tail(token) or EXTERNAL.search(before):
            continue
        if GENERATED_AFTER.match(text[m.end() :]):
            continue
        problems.append(Problem(citing, number, f"cites {token}, which is not in the tree"))


def sentence_start(text: str) -> str:
    """The text since the last sentence boundary (a full stop, question or exclamation mark, then a blank)."""
    ends = [m.end() for m in re.finditer(r"[.!?]\s", text)]
    return text[ends[-1] :] if ends else text


def check_document(tree: Tree, citing: str, number: int, token: str, before: str, after: str,
                   problems: list[Problem]) -> None:
    """A .md citation: the document is in the tree, and so is every section cited right after it."""
    doc = tree.resolve_doc(citing, token)
    if doc is None:
        if not (EXTERNAL.search(before) and "/" in token):  # another project's README, named by that project
            problems.append(Problem(citing, number, f"cites {token}, which is not in the tree"))
        return
    quoted = QUOTED_HEADING.match(after)
    titles = [HEADING_NUMBER.sub("", h) for h in tree.headings(doc)]  # "3. Packets" is cited as "Packets"
    if quoted and not any(t.startswith(quoted.group(1)) for t in titles):
        message = f'cites {token}, "{quoted.group(1)}"; {doc} has no such heading'
        problems.append(Problem(citing, number, message))
    cited = SECTIONS.match(after)
    if not cited:
        return
    for section in SECTION_ONE.findall(cited.group(0)):
        if section not in tree.sections(doc):
            message = f"cites {token} §{section}; {doc} has no section {section}"
            problems.append(Problem(citing, number, message))


def check_markdown_links(tree: Tree, citing: str, number: int, line: str, problems: list[Problem]) -> None:
    for m in MARKDOWN_LINK.finditer(line):
        target, _, anchor = m.group(1).partition("#")
        if "://" in target or target.startswith(("mailto:", "/")):
            continue
        resolved = os.path.normpath(os.path.join(os.path.dirname(citing), target)) if target else citing
        if not tree.exists(resolved):
            problems.append(Problem(citing, number, f"links to {m.group(1)}, which is not in the tree"))
        elif anchor and resolved.endswith(".md") and anchor not in tree.anchors(resolved):
            message = f"links to {m.group(1)}; {resolved} has no heading #{anchor}"
            problems.append(Problem(citing, number, message))


def check_file(tree: Tree, rel: str, problems: list[Problem]) -> None:
    name = os.path.basename(rel)
    ext = os.path.splitext(name)[1]
    if ext in C_LIKE:
        kind = "c"
    elif ext in HASH_COMMENTS or name == "CMakeLists.txt":
        kind = "hash"
    elif ext in MARKDOWN:
        kind = "md"
    else:
        return
    with open(os.path.join(tree.root, rel), encoding="utf-8", errors="replace") as f:
        text = f.read()
    if kind == "c":
        lines = c_like_comments(text)
    elif kind == "hash":
        lines = hash_comments(text)
    else:
        lines = markdown_lines(text)
    previous = (0, "")
    paragraph = ""
    history = rel == CHANGE_LOG
    for number, line in lines:
        if kind == "md":
            check_markdown_links(tree, rel, number, line, problems)
            if history:
                continue
            line = MARKDOWN_LINK.sub("]", line)
            paragraph = paragraph if previous[0] == number - 1 and line.strip() else ""
            check_text(tree, rel, number, line, problems, paragraph, sentence=True)
            paragraph += " " + line
        else:
            check_text(tree, rel, number, line, problems, previous[1] if previous[0] == number - 1 else "")
        previous = (number, line)


def check_tree(root: str) -> list[Problem]:
    tree = Tree(root)
    problems: list[Problem] = []
    for rel in sorted(tree.files):
        check_file(tree, rel, problems)
    return problems


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("--root", default=os.path.join(here, "..", ".."))
    args = parser.parse_args(argv)
    problems = check_tree(os.path.abspath(args.root))
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} citation(s) of files that are not in the tree", file=sys.stderr)
        return 1
    print("every file cited in comments and docs is in the tree")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
