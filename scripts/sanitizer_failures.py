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

When every failure is of that kind, names them on stderr, prints a CTest
regular expression matching exactly those tests (for `ctest -R`) and exits 0,
so the caller re-runs them; exits 1 when some failure is anything else (it
names those on stderr) or the file cannot be read.

The re-run selects tests by name, not with `ctest --rerun-failed`: that reads
test numbers back from LastTestsFailed.log, and after a run filtered with -E
those numbers named other tests (a CI run re-ran fusespeed.reuse in place of
gltfext.extensions).

Usage: sanitizer_failures.py JUNIT.xml | --self-test
"""
import re
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


# Characters special in CMake's regular expressions (cmake-commands(7), "Regex
# Specification"); a backslash makes each literal.
CMAKE_REGEX_SPECIAL = set("^$.[]*+?|()\\")


def ctest_regex(names):
    """A CTest -R expression that matches exactly the given test names."""
    escaped = ("".join("\\" + c if c in CMAKE_REGEX_SPECIAL else c for c in n) for n in names)
    return "^(" + "|".join(escaped) + ")$"


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
    # The re-run expression, checked the way CTest reads it (POSIX-like, whole name).
    regex_checks = [
        (["gltfext.extensions", "lightrender.matrix"],
         ["gltfext.extensions", "lightrender.matrix"],
         ["gltfextXextensions", "gltfext.extensions2", "fusespeed.reuse", "xlightrender.matrix"]),
        (["a+b(c)"], ["a+b(c)"], ["aab(c)", "a+bc"]),
    ]
    for names, match, reject in regex_checks:
        rx = re.compile(ctest_regex(names))
        for n in match + reject:
            if bool(rx.search(n)) != (n in match):
                print(f"sanitizer_failures self-test: {ctest_regex(names)} on {n!r} wrong", file=sys.stderr)
                failed += 1
    checks += regex_checks
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
    print("sanitizer_failures: LeakSanitizer's tracer crashed at exit in: " + " ".join(tracer_only)
          + " - running those once more", file=sys.stderr)
    print(ctest_regex(tracer_only))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
