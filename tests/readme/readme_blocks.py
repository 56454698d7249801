"""The command blocks of README.md that tests/readme runs, found by their markers.

A block the README shows a user is preceded by a marker line, an HTML comment the rendered page hides:

    <!-- readme-test: NAME -->
    ```sh
    ...
    ```

A marker may also name a paragraph whose first inline `code span` with a space in it is the command (the headline map
command under the picture). `<!-- readme-test: skip NAME: REASON -->` marks a block the test does not run,
with the reason it prints. Every fenced block in the sections the test covers must carry a marker, so a
block added to the README without a test fails the test instead of going unchecked.
"""

import re
from dataclasses import dataclass

MARKER = re.compile(r"^<!-- readme-test: (skip )?([a-z0-9-]+)(?:: (.*?))? -->\s*$")
FENCE = re.compile(r"^```(\w*)\s*$")


@dataclass
class Block:
    name: str
    text: str        # the block's lines, or the paragraph's command with its line breaks folded
    line: int        # 1-based line of the marker in README.md
    skip_reason: str  # "" when the test runs it


def _section_of(lines, index):
    for i in range(index, -1, -1):
        if lines[i].startswith("## "):
            return lines[i][3:].strip()
    return ""


def parse(readme_text, sections):
    """Returns ({name: Block}, [problems]) for the README text; `sections` are the `## ` headings whose
    fenced blocks must all be marked."""
    lines = readme_text.splitlines()
    blocks, problems = {}, []
    marked_fences = set()
    i = 0
    while i < len(lines):
        m = MARKER.match(lines[i])
        if not m:
            i += 1
            continue
        skip, name, reason = m.group(1) is not None, m.group(2), m.group(3) or ""
        if name in blocks:
            problems.append(f"README.md:{i + 1}: marker '{name}' appears twice")
        j = i + 1
        if j < len(lines) and FENCE.match(lines[j]):
            marked_fences.add(j)
            k = j + 1
            while k < len(lines) and not lines[k].startswith("```"):
                k += 1
            if k == len(lines):
                problems.append(f"README.md:{j + 1}: block '{name}' is never closed")
            text = "\n".join(lines[j + 1:k])
            i = k + 1
        else:
            # A paragraph: its first inline code span, which may run over several lines.
            k = j
            while k < len(lines) and lines[k].strip():
                k += 1
            paragraph = " ".join(line.strip() for line in lines[j:k])
            # The first span that holds a command (a program and its arguments), not a file name.
            spans = [x for x in re.findall(r"`([^`]+)`", paragraph) if " " in x.strip()]
            if not spans:
                problems.append(f"README.md:{i + 1}: marker '{name}' is followed by neither a block nor code")
                text = ""
            else:
                text = re.sub(r"\s+", " ", spans[0]).strip()
            i = k
        blocks[name] = Block(name, text, i + 1, reason if skip else "")
    for n, line in enumerate(lines):
        if FENCE.match(line) and n not in marked_fences and _section_of(lines, n) in sections:
            # Only opening fences: count fences above to tell an opening one from a closing one.
            opened = sum(1 for x in lines[:n] if x.startswith("```")) % 2 == 0
            if opened:
                problems.append(f"README.md:{n + 1}: a block in '{_section_of(lines, n)}' has no "
                                "<!-- readme-test: ... --> marker, so no test runs it")
    return blocks, problems


def commands(block_text):
    """The block's lines with comments and blank lines removed, continuation lines joined."""
    out, pending = [], ""
    for raw in block_text.splitlines():
        line = raw.rstrip()
        if line.endswith("\\"):
            pending += line[:-1] + " "
            continue
        line = pending + line
        pending = ""
        stripped = re.sub(r"\s+#.*$", "", line).strip()  # a trailing comment after a command
        if stripped and not stripped.startswith("#"):
            out.append(stripped)
    return out
