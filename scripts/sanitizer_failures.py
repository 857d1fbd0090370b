#!/usr/bin/env python3
"""Sort the failures of a CTest run under the sanitizers (its --output-junit
file) into those that LeakSanitizer's own exit-time check caused and all others.

LeakSanitizer stops every thread with a ptrace-based tracer to scan memory at
exit; that tracer sometimes dies of a segfault of its own ("Tracer caught
signal 11 ... LeakSanitizer has encountered a fatal error"), an open,
intermittent sanitizer runtime bug (google/sanitizers#1353) that says nothing
about the program. Such a failure is worth exactly one re-run of the test; any
real sanitizer report (an ASan error, a leak, undefined behaviour) or any other
failure is not.

Prints the names of failed tests whose output carries the tracer's signature
and no sanitizer report, one per line, and exits 0 when every failure is of
that kind (so the caller re-runs them), 1 when some failure is anything else
(it names those on stderr) or the file cannot be read.

Usage: sanitizer_failures.py JUNIT.xml | --self-test
"""
import sys
import xml.etree.ElementTree as ET

TRACER_CRASH = "LeakSanitizer has encountered a fatal error"
# Any of these means a sanitizer found something in the program: never re-run.
REPORTS = (
    "ERROR: AddressSanitizer",
    "ERROR: LeakSanitizer: detected memory leaks",
    "runtime error:",
    "SUMMARY: UndefinedBehaviorSanitizer",
    "SUMMARY: AddressSanitizer",
)


def classify(root):
    """(tracer_only, others): the names of the failed test cases of a JUnit tree."""
    tracer_only, others = [], []
    for case in root.iter("testcase"):
        if case.get("status") != "fail":
            continue
        name = case.get("name", "?")
        output = "".join(e.text or "" for e in case.iter("system-out"))
        output += "".join(e.text or "" for e in case.iter("failure"))
        output += "".join(e.get("message", "") for e in case.iter("failure"))
        if TRACER_CRASH in output and not any(r in output for r in REPORTS):
            tracer_only.append(name)
        else:
            others.append(name)
    return tracer_only, others


def self_test():
    """Each kind of failure CTest's JUnit output can hold, sorted as documented."""
    def junit(*cases):
        body = "".join(
            f'<testcase name="{n}" status="{st}"><failure message="{m}"/><system-out>{out}</system-out></testcase>'
            for n, st, m, out in cases)
        return ET.fromstring(f'<testsuite>{body}</testsuite>')
    tracer = "FAIL: exit 1\nTracer caught signal 11: addr=0x6b8\n==755==" + TRACER_CRASH + ".\n"
    checks = [
        (junit(("a", "fail", "", tracer), ("b", "run", "", "")), (["a"], [])),
        (junit(("a", "fail", "", "==1==ERROR: LeakSanitizer: detected memory leaks\n")), ([], ["a"])),
        (junit(("a", "fail", "", tracer + "x.cpp:3:5: runtime error: signed integer overflow\n")), ([], ["a"])),
        (junit(("a", "fail", "", tracer + "==1==ERROR: AddressSanitizer: heap-buffer-overflow\n")), ([], ["a"])),
        (junit(("a", "fail", "Timeout", "")), ([], ["a"])),
        (junit(("a", "fail", "", tracer), ("c", "fail", "", "FAIL: expected 0\n")), (["a"], ["c"])),
        (junit(("b", "run", "", tracer)), ([], [])),
    ]
    failed = 0
    for i, (tree, want) in enumerate(checks):
        got = classify(tree)
        if got != want:
            print(f"sanitizer_failures self-test case {i}: got {got}, want {want}", file=sys.stderr)
            failed += 1
    print(f"sanitizer_failures self-test: {len(checks) - failed} of {len(checks)} cases sorted as documented")
    return 1 if failed else 0


def main(argv):
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    if argv[1] == "--self-test":
        return self_test()
    try:
        root = ET.parse(argv[1]).getroot()
    except (OSError, ET.ParseError) as e:
        print(f"sanitizer_failures: cannot read {argv[1]}: {e}", file=sys.stderr)
        return 1
    tracer_only, others = classify(root)
    for name in others:
        print(f"sanitizer_failures: {name} failed for a reason other than LeakSanitizer's tracer", file=sys.stderr)
    if others or not tracer_only:
        return 1
    print("\n".join(tracer_only))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
