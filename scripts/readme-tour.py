#!/usr/bin/env python3
"""The README's tour: its commands run, their output compared with what the README shows.

The tour is the part of README.md between `<!-- tour -->` and `<!-- end tour -->`.
Each ```console block there holds one command (a line `$ ./build/nearcap ...`)
and the output the README shows for it.

  scripts/readme-tour.py --check [--nearcap BIN]    run every command, fail on a difference
  scripts/readme-tour.py --update [--nearcap BIN]   rewrite the blocks with today's output

The sentence before the tour names the run the README shows ("pasted from a
real run on DATE at commit HASH"): --update writes today's date and the
checked-out commit there, --check only that the sentence is there.

Times vary from run to run: every decimal number (`2703.38 ms`, the `ms`
column) and every number followed by ` ms` (a time printed with six
significant digits can come out whole: `147 ms`) is compared as a
placeholder, every other integer (pixel counts, cases, faces) exactly.
Outputs the commands write (`out/tour/...`) go to a temporary directory.
"""
import argparse
import datetime
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
BLOCK = re.compile(r"```console\n\$ (?P<command>[^\n]*)\n(?P<output>.*?)```", re.S)
RUN = re.compile(r"pasted from a(\s+)real run on \d{4}-\d{2}-\d{2} at commit [0-9a-f]+")
DECIMAL = re.compile(r"[ \t]*(\d+\.\d+(e[-+]\d+)?|\d+(?= ms\b))")


def tour_span(text):
    begin, end = text.find("<!-- tour -->"), text.find("<!-- end tour -->")
    if begin < 0 or end < begin:
        sys.exit("readme-tour: README.md has no <!-- tour --> ... <!-- end tour --> part")
    return begin, end


def run(command, nearcap, scratch):
    if not command.startswith("./build/nearcap "):
        sys.exit(f"readme-tour: a tour command must start with ./build/nearcap: {command}")
    args = command.split()[1:]
    args = [a.replace("out/tour", str(scratch)) for a in args]
    done = subprocess.run([nearcap] + args, cwd=ROOT, capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        sys.exit(f"readme-tour: `{command}` failed ({done.returncode}): {done.stderr.strip()}")
    return done.stdout.replace(str(scratch), "out/tour")


def masked(text):
    # The padding before a number is the column's width less the number's:
    # it goes with the number.
    return DECIMAL.sub(" #", text).rstrip() + "\n"


def main():
    parser = argparse.ArgumentParser()
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--check", action="store_true")
    mode.add_argument("--update", action="store_true")
    parser.add_argument("--nearcap", default=str(ROOT / "build" / "nearcap"))
    options = parser.parse_args()
    text = README.read_text()
    if not RUN.search(text[: tour_span(text)[0]]):
        sys.exit("readme-tour: README.md names no run before its tour (\"pasted from a real run on DATE at commit HASH\")")
    begin, end = tour_span(text)
    tour = text[begin:end]
    blocks = list(BLOCK.finditer(tour))
    if not blocks:
        sys.exit("readme-tour: the tour holds no ```console block")
    stale = []
    pieces, last = [], 0
    with tempfile.TemporaryDirectory() as scratch:
        for block in blocks:
            command = block.group("command")
            got = run(command, options.nearcap, Path(scratch))
            if masked(got) != masked(block.group("output")):
                stale.append((command, block.group("output"), got))
            pieces.append(tour[last:block.start("output")] + got.rstrip() + "\n")
            last = block.end("output")
    pieces.append(tour[last:])
    if options.update:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True)
        if commit.returncode != 0 or not commit.stdout.strip():
            sys.exit(f"readme-tour: no commit to name the run by (git rev-parse: {commit.stderr.strip()})")
        today = datetime.date.today().isoformat()
        head = RUN.sub(
            lambda m: f"pasted from a{m.group(1)}real run on {today} at commit {commit.stdout.strip()}", text[:begin], count=1
        )
        README.write_text(head + "".join(pieces) + text[end:])
        print(f"readme-tour: {len(blocks)} commands run, README.md's tour rewritten ({len(stale)} changed)")
        return 0
    for command, shown, got in stale:
        print(f"$ {command}\n--- README shows:\n{shown}--- it prints:\n{got}")
    if stale:
        print("README.md's tour is stale: run ./scripts/readme-tour.py --update and commit README.md",
              file=sys.stderr)
        return 1
    print(f"readme-tour: the {len(blocks)} commands print what README.md shows")
    return 0


if __name__ == "__main__":
    sys.exit(main())
