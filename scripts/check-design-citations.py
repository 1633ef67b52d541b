#!/usr/bin/env python3
"""Every citation of the design document in the tree must resolve: `docs/DESIGN.md §N` or `§N.M`
(also `§2, §4` and `§2, §3 and §6`) to a heading of docs/DESIGN.md ("## 4. ..." or "### 4.1 ..."),
a `DESIGN.md#anchor` link to a heading's anchor, and the path itself to docs/DESIGN.md (from the
repository root, or relative to the citing file). Code (engine/, app/, glsl/) must also not name an
issue ("issue 14"): comments state contracts and reasons, the story goes in commit messages. Prints
file:line: reason for each fault and exits 1; exits 0 when there is none.

    scripts/check-design-citations.py [--root DIR]    # the tree (default: this script's repository)
    scripts/check-design-citations.py --self-test     # the checker on a made-up tree with known faults

Files: `git ls-files` (tracked and untracked-but-not-ignored) where the root is a git checkout,
otherwise every file under the folders below; binary and non-UTF-8 files are skipped.
"""
import argparse
import os
import posixpath
import re
import subprocess
import sys
import tempfile

DESIGN = "docs/DESIGN.md"
FOLDERS = ["engine", "app", "glsl", "tests", "scripts", "docs", "assets", "cmake"]
TOP_FILES = ["README.md", "CMakeLists.txt"]
SELF = "scripts/check-design-citations.py"

HEADING = re.compile(r"^#{2,3}\s+(\d+(?:\.\d+)*)\.?\s+\S")
# The document's name, optionally with a path before it, an anchor, or a Markdown link target after
# it, then any list of sections: "§2", "§2, §4", "§2, §3 and §6". "DESIGN §5" (no .md) counts too.
CITATION = re.compile(
    r"(?P<path>[\w./-]*?)(?<![\w-])DESIGN(?P<md>\.md)?(?P<anchor>#[\w.-]+)?(?:\]\((?P<link>[^)\s]*)\))?"
    r"(?P<sections>(?:\s*(?:,|and|or|&)?\s*§\s?\d+(?:\.\d+)*)*)"
)
SECTION = re.compile(r"§\s?(\d+(?:\.\d+)*)")
# Folders of code, where "issue N" (any case) is history, not a contract.
CODE_FOLDERS = ("engine/", "app/", "glsl/")
ISSUE = re.compile(r"\bissues?(?:\s+#?|\s*#)\d+", re.IGNORECASE)


def github_anchor(heading_text):
    """The anchor GitHub gives a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[^\w\- ]", "", heading_text.strip().lower())
    return text.replace(" ", "-")


def design_headings(root):
    """Section numbers and anchors of docs/DESIGN.md's headings."""
    sections, anchors = set(), set()
    with open(os.path.join(root, DESIGN), encoding="utf-8") as f:
        for line in f:
            if line.startswith("#"):
                anchors.add(github_anchor(line.lstrip("#")))
            m = HEADING.match(line)
            if m:
                sections.add(m.group(1))
    return sections, anchors


def tree_files(root):
    try:
        out = subprocess.run(
            ["git", "-C", root, "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
            check=True, capture_output=True).stdout
        files = sorted({f for f in out.decode("utf-8").split("\0") if f})
        return [f for f in files if os.path.isfile(os.path.join(root, f))]
    except (OSError, subprocess.CalledProcessError):
        files = [f for f in TOP_FILES if os.path.isfile(os.path.join(root, f))]
        for folder in FOLDERS:
            for dirpath, dirnames, filenames in os.walk(os.path.join(root, folder)):
                dirnames[:] = sorted(d for d in dirnames if not d.startswith("."))
                for name in sorted(filenames):
                    files.append(os.path.relpath(os.path.join(dirpath, name), root).replace(os.sep, "/"))
        return files


def resolves_to_design(citing_file, path):
    """Whether `path` + DESIGN.md names docs/DESIGN.md, from the root or from the citing file's folder."""
    if posixpath.normpath(path + "DESIGN.md") == DESIGN:
        return True
    return posixpath.normpath(posixpath.join(posixpath.dirname(citing_file), path + "DESIGN.md")) == DESIGN


def check_line(rel, number, line, sections, anchors):
    problems = []
    for m in CITATION.finditer(line):
        cited = SECTION.findall(m.group("sections"))
        if not m.group("md") and not cited:
            continue  # the word DESIGN, not a citation
        where = f"{rel}:{number}"
        path = m.group("path")
        if not m.group("md"):
            problems.append(f"{where}: 'DESIGN §{cited[0]}' names no file: write '{DESIGN} §{cited[0]}'")
        elif not resolves_to_design(rel, path):
            problems.append(f"{where}: '{path}DESIGN.md' is not {DESIGN} (write '{DESIGN}')")
        link = m.group("link")  # [docs/DESIGN.md](TARGET) §N
        if link is not None:
            target, _, link_anchor = link.partition("#")
            if target and not (target.endswith("DESIGN.md") and resolves_to_design(rel, target[: -len("DESIGN.md")])):
                problems.append(f"{where}: the link '{link}' does not lead to {DESIGN}")
            if link_anchor and link_anchor not in anchors:
                problems.append(f"{where}: the link '{link}' names no heading of {DESIGN}")
        anchor = m.group("anchor")
        if anchor and anchor[1:] not in anchors:
            problems.append(f"{where}: '{anchor}' is no heading of {DESIGN}")
        for section in cited:
            if section not in sections:
                problems.append(f"{where}: §{section} is not a heading of {DESIGN} (it has §"
                                + ", §".join(sorted(sections, key=lambda s: [int(p) for p in s.split(".")])) + ")")
    return problems


def check_history(rel, number, line):
    """'issue N' in a line of code (engine/, app/, glsl/)."""
    if not rel.startswith(CODE_FOLDERS):
        return []
    return [f"{rel}:{number}: '{m.group(0)}' in code: say the contract or the reason, and leave the story to "
            "the commit message" for m in ISSUE.finditer(line)]


def check(root):
    """Returns the problems found in the tree at `root`, one 'file:line: reason' each."""
    if not os.path.isfile(os.path.join(root, DESIGN)):
        return [f"{DESIGN}: missing"]
    sections, anchors = design_headings(root)
    problems = []
    for rel in tree_files(root):
        if rel == SELF:
            continue  # quotes bad citations on purpose (the self-test)
        try:
            with open(os.path.join(root, rel), encoding="utf-8") as f:
                text = f.read()
        except (UnicodeDecodeError, OSError):
            continue
        if "\0" in text:
            continue
        cites = "DESIGN" in text
        for number, line in enumerate(text.splitlines(), start=1):
            if cites:
                problems += check_line(rel, number, line, sections, anchors)
            problems += check_history(rel, number, line)
    return problems


def self_test():
    """The checker on a made-up tree: the good citations pass, each bad one is reported at its line."""
    design = "# Design\n\n## 2. Conventions\n\n## 3. Decomposition\n\n### 3.1 With a ground plane\n\n## 9. Layers\n"
    files = {
        DESIGN: design,
        "engine/good.h": ("// docs/DESIGN.md §2\n// (docs/DESIGN.md §2, §3 and §9) and docs/DESIGN.md §3.1's cells\n"
                          "// the design (docs/DESIGN.md) and DESIGNATED words, a DESIGN decision\n"),
        "docs/good.md": ("See DESIGN.md §3, [the layers](DESIGN.md#9-layers), docs/DESIGN.md §9,\n"
                         "[docs/DESIGN.md](DESIGN.md) §3.1 and [§2](../docs/DESIGN.md#2-conventions).\n"),
        "engine/bad.h": ("// fine: docs/DESIGN.md §2\n// docs/DESIGN.md §4: no such section\n"
                         "// docs/DESIGN.md §2, §3.2\n// DESIGN.md §2 outside docs/\n// ../shared/DESIGN.md §3\n"
                         "// DESIGN §9 without the file\n"),
        "docs/bad.md": ("[layers](DESIGN.md#layers) and DESIGN.md#3-decomposition-methods\n"
                        "[DESIGN.md](shared/DESIGN.md) §2\n"),
        "docs/history.md": "Issue 14 moved the bias; tissue 3 is no issue.\n",
        "tests/env/history_test.cpp": "// the inputs issue 16 listed\n",
        "engine/history.cpp": "int x;  // tissue 3, reissued\n// Optimisations of issue 10\n",
        "glsl/history.frag": "// after Issues 14 and 18\n",
        "app/history.h": "// see #14 or issue#3\n",
    }
    expected = [
        "docs/bad.md:1: '#layers' is no heading",
        "docs/bad.md:1: '#3-decomposition-methods' is no heading",
        "docs/bad.md:2: the link 'shared/DESIGN.md' does not lead to docs/DESIGN.md",
        "engine/bad.h:2: §4 is not a heading",
        "engine/bad.h:3: §3.2 is not a heading",
        "engine/bad.h:4: 'DESIGN.md' is not docs/DESIGN.md",
        "engine/bad.h:5: '../shared/DESIGN.md' is not docs/DESIGN.md",
        "engine/bad.h:6: 'DESIGN §9' names no file",
        "engine/history.cpp:2: 'issue 10' in code",
        "glsl/history.frag:1: 'Issues 14' in code",
        "app/history.h:1: 'issue#3' in code",
    ]
    with tempfile.TemporaryDirectory() as root:  # not a git checkout: the folder walk
        for rel, text in files.items():
            os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
            with open(os.path.join(root, rel), "w", encoding="utf-8") as f:
                f.write(text)
        with open(os.path.join(root, "engine/binary.bin"), "wb") as f:
            f.write(b"\xff\xfe DESIGN.md \xa74 \0")
        problems = check(root)
    failures = [e for e in expected if not any(p.startswith(e) for p in problems)]
    unexpected = [p for p in problems if not any(p.startswith(e) for e in expected)]
    for e in failures:
        print(f"self-test: not reported: {e}", file=sys.stderr)
    for p in unexpected:
        print(f"self-test: reported wrongly: {p}", file=sys.stderr)
    if failures or unexpected:
        return 1
    print(f"self-test: {len(expected)} faults reported at their lines, the good lines passed")
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser.add_argument("--self-test", action="store_true")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    problems = check(args.root)
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        print(f"{len(problems)} fault(s): citations of {DESIGN} that do not resolve, or issues named in code",
              file=sys.stderr)
        return 1
    print(f"every citation of {DESIGN} resolves, and no code names an issue")
    return 0


if __name__ == "__main__":
    sys.exit(main())
