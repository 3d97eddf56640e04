#!/usr/bin/env python3
"""The README's tour runs as written.

usage: readme_tour.py SOURCE_DIR BUILD_DIR PYTHON

Reads the fenced code blocks of README.md's section "Five minutes with a robot" (with
markdown-it-py, as tests/doc_links.py does) and, in a fresh folder that holds links named
`build` and `examples` to BUILD_DIR and SOURCE_DIR/examples (the repository root as the
tour sees it):
- runs every `sh` block with bash -e, skipping its `cmake` lines (building the targets is
  the build's job: this test needs medspheres_cli, robot_distance and medspheres_python);
- runs every `python` block with PYTHON and PYTHONPATH=build/python, except the blocks
  that import cuRobo, which is not a dependency;
- checks that the `cpp` block, from its second line on, is the snippet that
  examples/robot_distance.cpp compiles (between "README snippet begins" and "ends").
Exits 0 when all of that holds, 1 with the failing block otherwise.
"""
import os
import pathlib
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import doc_links  # noqa: E402  (the shared Markdown parser and heading text)

SECTION = "Five minutes with a robot"


def tour_blocks(readme):
    """(language, code, line) of each fenced block in the tour section."""
    tokens = doc_links.parse(readme)
    inside, blocks = False, []
    for i, token in enumerate(tokens):
        if token.type == "heading_open" and token.tag == "h2":
            inside = doc_links.plain_text(tokens[i + 1]) == SECTION
        elif inside and token.type == "fence":
            blocks.append((token.info.strip(), token.content, token.map[0] + 1))
    return blocks


def example_snippet(source):
    lines = (source / "examples" / "robot_distance.cpp").read_text().splitlines()
    begin = next(i for i, l in enumerate(lines) if "README snippet begins" in l)
    end = next(i for i, l in enumerate(lines) if "README snippet ends" in l)
    body = lines[begin + 1:end]
    indent = min(len(l) - len(l.lstrip()) for l in body if l.strip())
    return [l[indent:] for l in body]


def main(argv):
    if len(argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    source, build, python = pathlib.Path(argv[1]).resolve(), pathlib.Path(argv[2]).resolve(), argv[3]
    blocks = tour_blocks(source / "README.md")
    kinds = [b[0] for b in blocks]
    if "sh" not in kinds or "python" not in kinds or "cpp" not in kinds:
        print("readme_tour: the section '%s' lacks an sh, python or cpp block (found %s)" %
              (SECTION, kinds))
        return 1
    env = dict(os.environ, PYTHONPATH=str(build / "python"))
    ran = 0
    with tempfile.TemporaryDirectory(prefix="readme_tour.") as tmp:
        os.symlink(build, os.path.join(tmp, "build"))
        os.symlink(source / "examples", os.path.join(tmp, "examples"))
        for kind, code, line in blocks:
            if kind == "cpp":
                if code.splitlines()[1:] != example_snippet(source):
                    print("README.md:%d: the cpp block is not examples/robot_distance.cpp's "
                          "snippet" % line)
                    return 1
                continue
            if kind == "python" and "curobo" in code:
                continue
            if kind == "sh":
                code = "\n".join(l for l in code.splitlines() if not l.startswith("cmake "))
                command = ["bash", "-e", "-c", code]
            elif kind == "python":
                command = [python, "-c", code]
            else:
                continue  # output shown as text
            done = subprocess.run(command, cwd=tmp, env=env, capture_output=True, text=True)
            if done.returncode != 0:
                print("README.md:%d: the %s block exits %d\n%s%s" %
                      (line, kind, done.returncode, done.stdout, done.stderr))
                return 1
            ran += 1
    print("readme_tour: %d blocks ran, the C++ block is the example's code" % ran)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
