"""Source-side math check of the rustdoc text (doc comments in src/, and docs/**/*.md).

Counts the doc lines that carry TeX, and those where Markdown or rustdoc would break it:
  escape  - a backslash before ASCII punctuation that Markdown eats (\\, \\{ \\; \\! written singly)
  newline - a doubled backslash before whitespace (Markdown leaves one: a TeX row break is lost)
  quote   - ' " -- or ... inside $...$ (rustdoc's smart punctuation rewrites them)
  outside - a TeX command outside $...$ and outside code (shown raw even with KaTeX)
Code blocks (```math included) and inline code are skipped: Markdown leaves them verbatim.
Usage: python3 source_check.py REPO_ROOT [-v]; exit 1 when a line is broken.
"""
import collections
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1])
verbose = "-v" in sys.argv
punct = re.escape("!\"#$%&'()*+,-./:;<=>?@[]^_`{|}~")
counts = collections.Counter()
files = sorted(root.glob("src/**/*.rs")) + sorted(
    p for p in root.glob("docs/**/*.md") if "node_modules" not in p.parts
)
for path in files:
    markdown = path.suffix == ".md"
    fence = False
    for number, line in enumerate(path.read_text().splitlines(), 1):
        if markdown:
            text = line
        else:
            m = re.match(r"\s*//[/!] ?(.*)", line)
            if not m:
                continue
            text = m.group(1)
        if re.match(r"\s*(```|~~~)", text):
            fence = not fence
            continue
        if fence:
            continue
        text = re.sub(r"`[^`]*`", "", text)
        if not re.search(r"\$|\\[A-Za-z]", text):
            continue
        counts["tex"] += 1
        bad = []
        # An odd run of backslashes before punctuation: Markdown consumes the last one.
        if re.search(r"(?<!\\)(\\\\)*\\[" + punct + "]", text):
            bad.append("escape")
        if re.search(r"(?<!\\)\\\\(\s|$)", text):
            bad.append("newline")
        spans = re.findall(r"\$\$?([^$]+)\$?\$", text)
        if any(re.search(r"['\"]|--|\.\.\.", s) for s in spans):
            bad.append("quote")
        outside = re.sub(r"\$[^$]*\$", "", text)
        if "$" not in outside and re.search(r"\\[A-Za-z]{2,}", outside):
            bad.append("outside")
        for b in bad:
            counts[b] += 1
        if bad:
            counts["broken"] += 1
            if verbose:
                print(f"{path.relative_to(root)}:{number}: {','.join(bad)}: {text.strip()[:140]}")
print(dict(counts))
sys.exit(1 if counts["broken"] else 0)
