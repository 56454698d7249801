#!/usr/bin/env python3
"""The function-length checker measures what a reader sees: bodies at namespace and class scope, with
braces in comments, strings and raw strings ignored, constructors with braced initialisers, and lambdas
counted inside their function; it fails on a function one line over the limit."""
import pathlib
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).parent))
import function_lengths  # noqa: E402


def body(lines):
    return "\n".join(f"  x += {i};" for i in range(lines))


class FunctionLengths(unittest.TestCase):
    def test_a_function_is_measured_from_its_declaration_to_its_closing_brace(self):
        text = "namespace a {\nint f(int x) {\n" + body(10) + "\n  return x;\n}\n}  // namespace a\n"
        self.assertEqual(function_lengths.functions(text), [(2, 14, "f")])

    def test_braces_in_comments_strings_and_raw_strings_do_not_count(self):
        text = ('void g() {\n  // a { in a comment\n  const char* s = "}{";\n  auto r = R"x(}})x";\n'
                "  /* { */ char c = '{';\n}\nvoid h() {}\n")
        self.assertEqual(function_lengths.functions(text), [(1, 6, "g"), (7, 7, "h")])

    def test_inline_methods_and_constructors_with_braced_initialisers(self):
        text = ("struct S {\n  S(int a) : v_{a}, w_(2) {\n    ++v_;\n  }\n  int get() const noexcept {\n"
                "    return v_;\n  }\n  int v_{0};\n  int w_ = 1;\n};\n")
        self.assertEqual(function_lengths.functions(text), [(2, 4, "S"), (5, 7, "get")])

    def test_lambdas_belong_to_their_function(self):
        text = "int main() {\n  auto l = [](int x) {\n    return x;\n  };\n  return l(1);\n}\n"
        self.assertEqual(function_lengths.functions(text), [(1, 6, "main")])

    def test_the_program_fails_on_one_line_over_the_limit_and_passes_at_it(self):
        with tempfile.TemporaryDirectory() as d:
            src = pathlib.Path(d, "lib")
            src.mkdir()
            f = src / "long.cpp"
            f.write_text("int f(int x) {\n" + body(148) + "\n  return x;\n}\n")  # 151 lines
            script = pathlib.Path(__file__).with_name("function_lengths.py")
            run = subprocess.run([sys.executable, script, d, "lib"], capture_output=True, text=True)
            self.assertEqual(run.returncode, 1, run.stdout + run.stderr)
            self.assertIn("lib/long.cpp:1: f is 151 lines", run.stderr)
            f.write_text("int f(int x) {\n" + body(147) + "\n  return x;\n}\n")  # 150 lines
            run = subprocess.run([sys.executable, script, d, "lib"], capture_output=True, text=True)
            self.assertEqual(run.returncode, 0, run.stdout + run.stderr)


if __name__ == "__main__":
    unittest.main()
