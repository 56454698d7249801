#!/usr/bin/env python3
"""Every file a comment or a doc cites is in the source tree (check_citations.py), and the checker does
report a citation of a file or section that does not exist.

Usage: test_citations.py [--source DIR] [unittest options]
"""

import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import check_citations  # noqa: E402

SOURCE = os.path.abspath(os.path.join(HERE, "..", ".."))


def write(root, rel, text):
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


class TreeCitations(unittest.TestCase):
    def test_every_file_cited_in_comments_and_docs_is_in_the_tree(self):
        problems = check_citations.check_tree(SOURCE)
        self.assertEqual([str(p) for p in problems], [])


class CheckerReportsWhatIsMissing(unittest.TestCase):
    """A small tree (not a git checkout, so the checker walks it) with one citation per case."""

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.root = self.dir.name
        write(self.root, "docs/guide.md", "# Guide\n\n## 3. Packets\n\n### 3.2 Blocks\n\nText.\n")
        write(self.root, "lib/include/ogf/lib/real_header.hpp", "// A header.\n")
        write(self.root, "lib/src/real_source.cpp", '#include "ogf/lib/real_header.hpp"\n')

    def tearDown(self):
        self.dir.cleanup()

    def problems_for(self, rel, text):
        write(self.root, rel, text)
        return [p.message for p in check_citations.check_tree(self.root) if p.path == rel]

    def test_made_up_document_in_a_comment_is_reported(self):
        found = self.problems_for("lib/src/a.cpp", "// See docs/wire-layout.md §3.2 for the bytes.\nint a;\n")
        self.assertEqual(found, ["cites docs/wire-layout.md, which is not in the tree"])

    def test_bare_name_of_a_missing_document_is_reported(self):
        found = self.problems_for("lib/src/a.cpp", "int a;  // the rule of velodyne.md §4.3\n")
        self.assertEqual(found, ["cites velodyne.md, which is not in the tree"])

    def test_missing_section_of_an_existing_document_is_reported(self):
        found = self.problems_for("lib/src/a.cpp", "/* docs/guide.md §3.2 and §3.7 */\n")
        self.assertEqual(found, ["cites docs/guide.md §3.7; docs/guide.md has no section 3.7"])

    def test_document_beside_the_tree_is_reported(self):
        found = self.problems_for("tools/run.sh", "#!/bin/sh\n# facts from ../shared/docs/velodyne.md\n")
        self.assertEqual(found, ["cites ../shared/docs/velodyne.md, which is beside the tree, not in it"])

    def test_made_up_source_file_is_reported(self):
        found = self.problems_for("lib/src/a.cpp", "// as made_up_decoder.hpp does\n")
        self.assertEqual(found, ["cites made_up_decoder.hpp, which is not in the tree"])

    def test_path_from_a_top_level_folder_must_exist_as_written(self):
        found = self.problems_for("lib/src/a.cpp", "// lib/src/real_header.hpp and lib/src/real_source.cpp\n")
        self.assertEqual(found, ["cites lib/src/real_header.hpp, which is not in the tree"])

    def test_missing_heading_named_after_a_document_is_reported(self):
        found = self.problems_for("lib/src/a.cpp", '// docs/guide.md, "Packets"; docs/guide.md, "Scans"\n')
        self.assertEqual(found, ['cites docs/guide.md, "Scans"; docs/guide.md has no such heading'])

    def test_broken_markdown_link_and_anchor_are_reported(self):
        found = self.problems_for(
            "README.md",
            "[guide](docs/guide.md#32-blocks), [gone](docs/gone.md), [bad](docs/guide.md#4-time)\n",
        )
        self.assertEqual(
            found,
            [
                "links to docs/gone.md, which is not in the tree",
                "links to docs/guide.md#4-time; docs/guide.md has no heading #4-time",
            ],
        )

    def test_change_log_may_name_removed_files_but_its_links_must_resolve(self):
        found = self.problems_for(
            "CHANGELOG.md",
            "- `lib/include/ogf/lib/gone.hpp` is removed; see [the guide](docs/guide.md), [gone](docs/gone.md)\n",
        )
        self.assertEqual(found, ["links to docs/gone.md, which is not in the tree"])
        self.assertEqual(
            self.problems_for("docs/notes.md", "- `lib/include/ogf/lib/gone.hpp` is removed\n"),
            ["cites lib/include/ogf/lib/gone.hpp, which is not in the tree"],
        )

    def test_existing_files_sections_and_other_projects_files_pass(self):
        text = (
            "// docs/guide.md §3 and §3.2; real_header.hpp, ogf/lib/real_header.hpp,\n"
            "// lib/src/real_source.cpp;\n"
            "// 2.304 us per firing (ros rawdata.h:75-79; vd packet_decoder.cpp:188); data in\n"
            "// ../shared/data/real/capture.pcap; writes DIR/sim.yaml and FILE.md.\n"
            'const char* s = "not a comment: gone.md";\n'
        )
        self.assertEqual(self.problems_for("lib/src/a.cpp", text), [])


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "--source":
        SOURCE = os.path.abspath(sys.argv[2])
        del sys.argv[1:3]
    unittest.main(verbosity=2)
