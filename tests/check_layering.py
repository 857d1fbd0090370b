#!/usr/bin/env python3
"""Fails when an #include runs the wrong way between voxbake's folders.

The folder a source file lives in is its tier (CMakeLists.txt builds each tier
from its folders, README "Layout"):

  core  libvox/core libvox/render formats/core tools/cli    the launcher `vox`
  bake  libvox/mesh formats/mesh formats/scene tools/bake   vox-bake.so, no OpenVDB
  full  libvox/scene formats/vdb formats/pagefile formats/image formats/export
        tools/cmds
                                                             vox-cmds.so

Rules:
  1. a file includes project headers of its own tier or a lower one only
     (core < bake < full), so a light binary never needs the scene model;
  2. core and bake files include no OpenVDB, OpenImageIO, OpenEXR or libpng header;
  3. libvox/ includes nothing from formats/ or tools/; formats/ nothing from tools/;
  4. every source file of libvox/, formats/ and tools/ lives in a tier folder.

Usage: check_layering.py [SOURCE_DIR]   exit 0 when every rule holds, 1 otherwise.
       check_layering.py --self-test      checks that each rule catches a violation.
"""
import os
import re
import sys

TIERS = {
    "libvox/core": 0, "libvox/render": 0, "formats/core": 0, "tools/cli": 0,
    "libvox/mesh": 1, "formats/mesh": 1, "formats/scene": 1, "tools/bake": 1,
    "libvox/scene": 2, "formats/vdb": 2, "formats/pagefile": 2, "formats/image": 2, "formats/export": 2,
    "tools/cmds": 2,
}
TIER_NAMES = ["core", "bake", "full"]
HEAVY = re.compile(r"^(openvdb|nanovdb|OpenImageIO|OpenEXR|Imf|Imath|png\.h)")
PART = {"libvox": 0, "formats": 1, "tools": 2}
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def tier_of(path):
    folder = os.path.dirname(path)
    return TIERS.get(folder)


def check(root):
    problems = []
    for top in PART:
        for dirpath, _, names in os.walk(os.path.join(root, top)):
            for name in sorted(names):
                if not name.endswith((".h", ".cpp")):
                    continue
                rel = os.path.relpath(os.path.join(dirpath, name), root)
                tier = tier_of(rel)
                if tier is None:
                    problems.append(f"{rel}: not in a tier folder ({', '.join(sorted(TIERS))})")
                    continue
                with open(os.path.join(root, rel), encoding="utf-8") as f:
                    for lineno, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        bracket, inc = m.groups()
                        where = f"{rel}:{lineno}: #include {inc}"
                        if bracket == "<":
                            if tier < 2 and HEAVY.match(inc):
                                problems.append(f"{where}: a {TIER_NAMES[tier]}-tier file includes a "
                                                f"full-tier library header (move the code to a full-tier folder)")
                            continue
                        inc_top = inc.split("/")[0]
                        if inc_top not in PART:
                            continue
                        if PART[inc_top] > PART[rel.split("/")[0]]:
                            problems.append(f"{where}: {rel.split('/')[0]}/ must not include {inc_top}/")
                        inc_tier = tier_of(inc)
                        if inc_tier is None:
                            problems.append(f"{where}: header outside every tier folder")
                        elif inc_tier > tier:
                            problems.append(f"{where}: a {TIER_NAMES[tier]}-tier file includes a "
                                            f"{TIER_NAMES[inc_tier]}-tier header")
    return problems


def self_test():
    """Each rule, broken once in a scratch tree, must be reported."""
    import tempfile
    cases = {
        "libvox/core/a.h": '#include "libvox/scene/scene.h"',        # rule 1
        "formats/mesh/b.cpp": "#include <openvdb/openvdb.h>",        # rule 2
        "libvox/scene/c.cpp": '#include "formats/vdb/scene_vdb.h"',  # rule 3
        "formats/d.h": "#pragma once",                               # rule 4
    }
    failed = 0
    for path, line in cases.items():
        with tempfile.TemporaryDirectory() as root:
            os.makedirs(os.path.join(root, os.path.dirname(path)), exist_ok=True)
            with open(os.path.join(root, path), "w") as f:
                f.write(line + "\n")
            if not check(root):
                print(f"self-test: '{line}' in {path} was not reported")
                failed += 1
    with tempfile.TemporaryDirectory() as root:  # and a clean tree passes
        os.makedirs(os.path.join(root, "tools/cmds"))
        with open(os.path.join(root, "tools/cmds/e.cpp"), "w") as f:
            f.write('#include "libvox/scene/scene.h"\n#include <openvdb/openvdb.h>\n')
        if check(root):
            print("self-test: a full-tier file including the scene model was reported")
            failed += 1
    print(f"check_layering self-test: {failed} failure(s)")
    return 1 if failed else 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    problems = check(root)
    for p in problems:
        print(p)
    print(f"check_layering: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
