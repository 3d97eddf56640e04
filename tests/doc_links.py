#!/usr/bin/env python3
"""Every relative link of the documentation resolves.

usage: doc_links.py SOURCE_DIR [FILE.md ...]   (default: README.md and docs/*.md)
       doc_links.py --self-test

A link or image in a Markdown file (found by markdown-it-py, CommonMark with tables, as
GitHub renders them) whose target has no URL scheme must name a file or folder of the
source tree (tracked by git when SOURCE_DIR is a git work tree), relative to the linking
file's folder (or to SOURCE_DIR for a target that starts with "/"). A #fragment must be a
heading's anchor in the target Markdown file (GitHub's rule, `anchor` below), or GitHub's
line anchor #Ln / #Ln-Lm within a file's lines. Prints each broken link as
FILE:LINE: TARGET: PROBLEM and exits 1 when there is one, 0 otherwise; 2 for bad usage.
"""
import os
import pathlib
import subprocess
import sys
import tempfile
import unicodedata
import urllib.parse

try:
    from markdown_it import MarkdownIt
except ImportError:
    sys.exit("doc_links: needs the Python package markdown_it (Debian: python3-markdown-it, "
             "which .ci/install-deps installs)")

PARSER = MarkdownIt("commonmark").enable("table")


def plain_text(inline):
    """The text of an inline token as GitHub's anchor sees it: markup dropped, code kept."""
    parts = []
    for child in inline.children or []:
        if child.type in ("text", "code_inline"):
            parts.append(child.content)
        elif child.type in ("softbreak", "hardbreak"):
            parts.append(" ")
        elif child.type == "image":
            parts.append(plain_text(child))
    return "".join(parts)


def anchor(heading):
    """GitHub's anchor of a heading (github-slugger): lower case; every character that is
    not a letter, a digit, a mark, a connector (_), a hyphen or a space dropped; each
    space a hyphen."""
    kept = []
    for ch in heading.strip().lower():
        category = unicodedata.category(ch)
        if ch == " ":
            kept.append("-")
        elif ch == "-" or category[0] in "LNM" or category == "Pc":
            kept.append(ch)
    return "".join(kept)


def parse(path):
    return PARSER.parse(path.read_text(encoding="utf-8"))


def anchors_of(path):
    """The anchors of a Markdown file's headings; a repeated one gets -1, -2, ... as on GitHub."""
    tokens = parse(path)
    seen, result = {}, set()
    for i, token in enumerate(tokens):
        if token.type != "heading_open":
            continue
        base = anchor(plain_text(tokens[i + 1]))
        slug = base if base not in seen else "%s-%d" % (base, seen[base])
        seen[base] = seen.get(base, 0) + 1
        result.add(slug)
    return result


def links_of(path):
    """(line, target) of every link and image of a Markdown file."""
    for token in parse(path):
        if token.type != "inline":
            continue
        line = token.map[0] + 1 if token.map else 0
        stack = list(token.children or [])
        while stack:
            child = stack.pop(0)
            if child.type in ("softbreak", "hardbreak"):
                line += 1  # the next line of the paragraph
            elif child.type == "link_open":
                yield line, child.attrGet("href")
            elif child.type == "image":
                yield line, child.attrGet("src")
                stack[:0] = child.children or []


def tracked_paths(root):
    """Files git tracks under root, and their folders; None when root is not a git work tree."""
    try:
        out = subprocess.run(["git", "-C", str(root), "ls-files", "-z"], capture_output=True,
                             check=True).stdout.decode("utf-8")
    except (OSError, subprocess.CalledProcessError):
        return None
    paths = set()
    for name in filter(None, out.split("\0")):
        parts = pathlib.PurePosixPath(name).parts
        for k in range(1, len(parts) + 1):
            paths.add(pathlib.PurePosixPath(*parts[:k]))
    return paths


class Checker:
    def __init__(self, root):
        self.root = pathlib.Path(root).resolve()
        self.tracked = tracked_paths(self.root)
        self.anchor_cache = {}

    def problem(self, source, target):
        """Why target, linked from the file source, does not resolve; None when it does."""
        parts = urllib.parse.urlsplit(target)
        if parts.scheme or target.startswith("//"):
            return None  # a URL: not checked here
        path = urllib.parse.unquote(parts.path)
        fragment = urllib.parse.unquote(parts.fragment)
        if not path:
            dest = source
        elif path.startswith("/"):
            dest = self.root / path.lstrip("/")
        else:
            dest = source.parent / path
        dest = pathlib.Path(os.path.normpath(dest))
        try:
            relative = pathlib.PurePosixPath(dest.relative_to(self.root).as_posix())
        except ValueError:
            return "outside the source tree"
        if not dest.exists():
            return "no such file or folder"
        if self.tracked is not None and str(relative) != "." and relative not in self.tracked:
            return "not tracked by git (a clone lacks it)"
        if not parts.fragment:
            return None
        if dest.is_file() and dest.suffix.lower() == ".md":
            if dest not in self.anchor_cache:
                self.anchor_cache[dest] = anchors_of(dest)
            if fragment not in self.anchor_cache[dest]:
                return "no heading with anchor #%s in %s" % (fragment, relative)
            return None
        if dest.is_file() and fragment.startswith("L"):
            bounds = fragment[1:].split("-L")
            if len(bounds) <= 2 and all(b.isdigit() for b in bounds):
                lines = dest.read_text(encoding="utf-8", errors="replace").count("\n") + 1
                if all(1 <= int(b) <= lines for b in bounds):
                    return None
                return "line anchor #%s beyond the file's %d lines" % (fragment, lines)
        return "fragment #%s on a file that is not Markdown" % fragment

    def check(self, files):
        broken = []
        for path in files:
            path = pathlib.Path(path).resolve()
            for line, target in links_of(path):
                why = self.problem(path, target)
                if why:
                    broken.append("%s:%d: %s: %s" % (path.relative_to(self.root), line, target, why))
        return broken


def self_test():
    """The checker against files whose broken links are known (anchor rule, fragments, paths)."""
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        (root / "docs").mkdir()
        (root / "src").mkdir()
        (root / "src" / "a.h").write_text("one\ntwo\nthree\n")
        (root / "docs" / "page.md").write_text(
            "# Robots: `medspheres robot`\n\n## Robots: `medspheres robot`\n\n"
            "## What a MoveIt user would change\n\n## Certified queries: bounds (inner, outer)\n\n"
            "| a | b |\n|---|---|\n| [table](#what-a-moveit-user-would-change) | x |\n")
        (root / "README.md").write_text("\n".join([
            "# Top", "",
            "[ok](docs/page.md#robots-medspheres-robot)",
            "[ok repeated](docs/page.md#robots-medspheres-robot-1)",
            "[ok punctuation](docs/page.md#certified-queries-bounds-inner-outer)",
            "[ok self](#top) [ok folder](src) [ok line](src/a.h#L2-L3) ![ok image](src/a.h)",
            "[ok url](https://example.org/x#y) [ok reference][r]", "",
            "[bad file](docs/nope.md)",
            "[bad anchor](docs/page.md#robots)",
            "[bad repeat](docs/page.md#robots-medspheres-robot-2)",
            "[bad line](src/a.h#L9)",
            "[bad fragment](src/a.h#top)",
            "[bad outside](../x.md)",
            "![bad image](docs/images/none.png)",
            "[bad reference][s]", "",
            "[r]: docs/page.md#what-a-moveit-user-would-change",
            "[s]: docs/page.md#nowhere", ""]))
        broken = Checker(root).check([root / "README.md", root / "docs" / "page.md"])
        got = sorted(b.split(": ")[0].split(":", 1)[1] + " " + b.split(": ")[1] for b in broken)
        want = sorted(["9 docs/nope.md", "10 docs/page.md#robots",
                       "11 docs/page.md#robots-medspheres-robot-2", "12 src/a.h#L9",
                       "13 src/a.h#top", "14 ../x.md", "15 docs/images/none.png",
                       "16 docs/page.md#nowhere"])
        if got != want:
            print("doc_links self-test: expected broken\n  %s\ngot\n  %s" %
                  ("\n  ".join(want), "\n  ".join(broken) or "(none)"))
            return 1
        total = sum(1 for f in ("README.md", "docs/page.md") for _ in links_of(root / f))
    print("doc_links self-test: the %d planted broken links found, the other %d passed" %
          (len(want), total - len(want)))
    return 0


def main(argv):
    if argv[1:] == ["--self-test"]:
        return self_test()
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    root = pathlib.Path(argv[1])
    files = [pathlib.Path(f) for f in argv[2:]] or \
        [root / "README.md"] + sorted((root / "docs").glob("*.md"))
    broken = Checker(root).check(files)
    for line in broken:
        print(line)
    print("doc_links: %d file(s), %s" % (len(files), "%d broken link(s)" % len(broken)
                                           if broken else "every relative link resolves"))
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
