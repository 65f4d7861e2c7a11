#!/usr/bin/env python3
"""Checks every relative link of README.md, data/README.md and docs/**/*.md:
the file must exist and, for a link to a heading (page.md#anchor), the
heading too (GitHub's anchors: lower case, punctuation dropped, spaces to
hyphens, -1, -2 ... for repeats).  Prints each broken link; exit status 1 if any.

  ./scripts/check-doc-links.py
"""
import os
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def slug(heading):
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def anchors(page):
    found, seen, fenced = set(), {}, False
    for line in page.read_text().splitlines():
        if line.startswith("```"):
            fenced = not fenced
            continue
        heading = None if fenced else re.match(r"^#+\s+(.*)", line)
        if heading:
            s = slug(heading.group(1))
            n = seen.get(s, 0)
            seen[s] = n + 1
            found.add(s if n == 0 else f"{s}-{n}")
    return found


def main():
    pages = [ROOT / "README.md", ROOT / "data" / "README.md"] + sorted((ROOT / "docs").rglob("*.md"))
    broken = 0
    for page in pages:
        text = re.sub(r"```.*?```", "", page.read_text(), flags=re.S)
        for link in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"[a-z]+:", link):
                continue
            path, _, fragment = link.partition("#")
            target = (page.parent / path).resolve() if path else page
            where = os.path.relpath(page, ROOT)
            if not target.exists():
                print(f"{where}: {link}: no such file")
                broken += 1
            elif fragment and target.suffix == ".md" and fragment not in anchors(target):
                print(f"{where}: {link}: no such heading")
                broken += 1
    print(f"check-doc-links: {len(pages)} pages, {broken} broken links")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
