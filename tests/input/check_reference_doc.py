#!/usr/bin/env python3
"""A document holds the output of a rodsolve flag between its GENERATED markers; this test fails
when the two differ (the code's tables changed, the docs did not):

    check_reference_doc.py RODSOLVE docs/user/input.md                      (--input-reference)
    check_reference_doc.py RODSOLVE docs/user/capabilities.md --capabilities
"""
import subprocess
import sys


def main():
    rodsolve, doc = sys.argv[1], sys.argv[2]
    flag = sys.argv[3] if len(sys.argv) > 3 else "--input-reference"
    generated = subprocess.run([rodsolve, flag], capture_output=True, text=True,
                               check=True).stdout.strip()
    text = open(doc, encoding="utf-8").read()
    begin = text.index(f"<!-- BEGIN GENERATED: rodsolve {flag} -->")
    end = text.index("<!-- END GENERATED -->")
    documented = text[begin:end].split("\n", 1)[1].strip()
    if documented != generated:
        print(f"{doc} is out of date; regenerate the block between its markers with "
              f"`build/rodsolve {flag}`")
        for i, (a, b) in enumerate(zip(documented.splitlines(), generated.splitlines())):
            if a != b:
                print(f"first difference at generated line {i + 1}:\n  doc: {a}\n  now: {b}")
                break
        print("0 passed, 1 failed")
        return 1
    print("1 passed, 0 failed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
