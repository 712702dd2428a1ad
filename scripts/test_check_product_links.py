#!/usr/bin/env python3
"""The path check of scripts/check_product_links.py (check_strings) on small programs compiled
into a scratch install prefix: a -g build, whose debug information names its sources by design,
passes; a path compiled into the code as a string, absolute or relative to the data folder,
fails and is named.

  scripts/test_check_product_links.py [--junit FILE]
"""
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_product_links import check_strings  # noqa: E402
from junit import run_unit_tests  # noqa: E402


class PathCheck(unittest.TestCase):
    def setUp(self):
        self.scratch = tempfile.TemporaryDirectory()
        self.checkout = os.path.join(self.scratch.name, "checkout")
        self.prefix = os.path.join(self.scratch.name, "install")
        os.makedirs(self.checkout)
        os.makedirs(os.path.join(self.prefix, "lib"))

    def tearDown(self):
        self.scratch.cleanup()

    def install(self, name, code, flags=()):
        """Compiles code from a source file inside the checkout into INSTALL/lib/name."""
        source = os.path.join(self.checkout, name + ".c")
        with open(source, "w") as out:
            out.write(code)
        subprocess.run(["cc", *flags, source, "-o", os.path.join(self.prefix, "lib", name)],
                       check=True, cwd=self.checkout)

    def test_debug_information_is_left_out(self):
        self.install("node", "int main(void) { return 0; }\n", ["-g"])
        problems, files = check_strings(self.prefix, self.checkout)
        self.assertEqual(files, 1)
        self.assertEqual(problems, [])

    def test_an_absolute_source_path_in_the_code_is_named(self):
        self.install("node", '#include <stdio.h>\nint main(void) { puts("%s/config/a.yaml"); '
                     'return 0; }\n' % self.checkout, ["-g"])
        problems, _ = check_strings(self.prefix, self.checkout)
        self.assertEqual(len(problems), 1, problems)
        self.assertIn("lib/node contains the path", problems[0])
        self.assertIn(self.checkout + "/config/a.yaml", problems[0])

    def test_a_relative_path_to_the_data_folder_is_named(self):
        self.install("node", '#include <stdio.h>\nint main(void) { puts("../shared/data"); '
                     'return 0; }\n')
        problems, _ = check_strings(self.prefix, self.checkout)
        self.assertEqual(len(problems), 1, problems)
        self.assertIn("../shared/data", problems[0])



if __name__ == "__main__":
    sys.exit(run_unit_tests(sys.modules[__name__], "product_links_unit",
                            __doc__.split("\n\n")[0]))
