#!/usr/bin/env python3
"""Numbers that cannot drift: the documents' quoted numbers against the data they come from.

Run from anywhere: `python3 .ci/check-numbers.py [-v]` (Python 3 standard library only).
Exits 1 naming every file, quoted number and CSV value that disagree.

1. Dataset numbers. A number quoted from a CSV carries a marker right after it:

       DE 0.01339<!-- check: de.csv stk=0.1 de -->

   `check:` then the CSV (relative to the Markdown file's folder, or to the repository root
   when it starts with `paper-figures/`), zero or more `column=value` filters that pick one
   row (numbers compare as numbers; quote a value with spaces: case="h=0.3mm layers=5"), and
   the column. Optional last tokens: `x100` (the quote
   is a percentage of the value), `abs` (the quote is the value's magnitude). The quote must
   equal the CSV value rounded to the quote's own decimals. Numbers measured outside the
   shipped data (issue 58's four-mesh runs, for example) are marked `<!-- outside: why -->`
   and not checked against a CSV.

   Checked files: README.md (its figure table is where the markers are) and every
   `paper-figures/*/NOTES.md`. Each NOTES.md opening (from the first line to its first `## `
   heading) must be at most 40 lines, and one whose folder ships a CSV must quote at least one
   number through a marker.

2. ARCHITECTURE.md against the tree. Every `name.rs` and `folder/` it names in its `src/` and
   `tests/` trees exists in that tree (under the top-level folder the entry belongs to), every
   backticked module path (`particle::dynamics`, `flow::openfoam::octree`) resolves to a module
   of src/ (a trailing item must be defined in that module's file), every test module path
   after `cargo test --test suite` resolves to a module of tests/suite, and every backticked
   repository path (`src/…`, `tests/…`, `examples/…`, `cases/…`, `paper-figures/…`,
   `python/…`, `docs/…`, `benches/…`) in ARCHITECTURE.md, README.md and the NOTES openings
   exists.
"""

import csv
import re
import shlex
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VERBOSE = "-v" in sys.argv[1:]
OPENING_MAX = 40

# A quoted number: optional sign (ASCII or U+2212), digits with thin/narrow spaces as
# thousands separators, optional decimals.
NUMBER = r"([+\-\u2212]?\d+(?:[\u2009\u202f ]\d{3})*(?:\.\d+)?)"
MARKER = re.compile(NUMBER + r"\s*<!--\s*check:\s*(.*?)\s*-->")
ANY_MARKER = re.compile(r"<!--\s*check:")
REPO_DIRS = ("src/", "tests/", "examples/", "cases/", "paper-figures/", "python/", "docs/",
             "benches/", "reference-data/", "scenes/", ".ci/")

errors = []
counts = {}


def fail(path, message):
    errors.append(f"{path.relative_to(ROOT)}: {message}")


def parse_number(text):
    text = text.replace("\u2212", "-").replace("\u2009", "").replace("\u202f", "").replace(" ", "")
    return float(text), (len(text.split(".")[1]) if "." in text else 0)


_csv_cache = {}


def read_csv(path):
    if path not in _csv_cache:
        with open(path, newline="") as f:
            _csv_cache[path] = list(csv.DictReader(f))
    return _csv_cache[path]


def same(cell, wanted):
    try:
        return float(cell) == float(wanted)
    except ValueError:
        return cell.strip() == wanted


def check_marker(md, quoted, spec):
    tokens = shlex.split(spec)
    if len(tokens) < 2:
        fail(md, f"marker `{spec}` needs a CSV and a column")
        return
    scale, magnitude = 1.0, False
    while tokens and tokens[-1] in ("x100", "abs"):
        if tokens.pop() == "x100":
            scale = 100.0
        else:
            magnitude = True
    name, *filters, column = tokens
    path = ROOT / name if name.startswith("paper-figures/") else md.parent / name
    if not path.is_file():
        fail(md, f"{quoted}: no CSV {name}")
        return
    rows = read_csv(path)
    for flt in filters:
        if "=" not in flt:
            fail(md, f"{quoted}: filter `{flt}` is not column=value")
            return
        key, value = flt.split("=", 1)
        if rows and key not in rows[0]:
            fail(md, f"{quoted}: {name} has no column {key}")
            return
        rows = [r for r in rows if same(r[key], value)]
    if len(rows) != 1:
        fail(md, f"{quoted}: {name} {' '.join(filters)} picks {len(rows)} rows, not one")
        return
    if column not in rows[0]:
        fail(md, f"{quoted}: {name} has no column {column}")
        return
    value = float(rows[0][column]) * scale
    if magnitude:
        value = abs(value)
    number, decimals = parse_number(quoted)
    if abs(round(value, decimals) - number) > 0.51 * 10.0 ** (-decimals):
        fail(md, f"quotes {quoted} where {name} ({' '.join(filters)}) {column} is "
                 f"{rows[0][column]} (rounded to {decimals} decimals: {round(value, decimals):.{decimals}f})")
        return
    counts[md] = counts.get(md, 0) + 1
    if VERBOSE:
        print(f"  ok {md.relative_to(ROOT)}: {quoted} = {name} {' '.join(filters)} {column} {rows[0][column]}")


def check_markers(md, text):
    found = MARKER.findall(text)
    if len(found) != len(ANY_MARKER.findall(text)):
        fail(md, "a `<!-- check: … -->` marker does not follow a number directly")
    for quoted, spec in found:
        check_marker(md, quoted, spec)


def opening(text):
    lines = text.split("\n")
    for k, line in enumerate(lines[1:], start=1):
        if line.startswith("## "):
            return "\n".join(lines[:k]), k
    return text, len(lines)


def check_paths(md, text):
    for token in re.findall(r"`([^`\s]+)`", text):
        token = token.rstrip(".,;:")
        if not token.startswith(REPO_DIRS) or any(c in token for c in "*<>{}…$"):
            continue
        if re.search(r"/[xyk]/", token) or token.endswith(("/x", "/y")):  # placeholders (src/x/y.rs)
            continue
        path = token.split(":")[0]
        if not (ROOT / path).exists():
            fail(md, f"names `{token}`, which is not in the tree")


# ---------------------------------------------------------------------------------------------
# 1. dataset numbers

readme = ROOT / "README.md"
text = readme.read_text()
check_markers(readme, text)
check_paths(readme, text)
for notes in sorted((ROOT / "paper-figures").glob("*/NOTES.md")):
    text = notes.read_text()
    check_markers(notes, text)
    head, length = opening(text)
    check_paths(notes, head)
    if length > OPENING_MAX:
        fail(notes, f"opening is {length} lines (at most {OPENING_MAX} before the first `## `)")
    if any(notes.parent.glob("*.csv")) and not MARKER.search(head):
        fail(notes, "its opening quotes no number through a `<!-- check: … -->` marker")

# ---------------------------------------------------------------------------------------------
# 2. ARCHITECTURE.md against the tree

arch = ROOT / "ARCHITECTURE.md"
text = arch.read_text()
check_paths(arch, text)
blocks = re.findall(r"```\n(.*?)```", text, flags=re.S)


def tree_names(block, base):
    """Each `x.rs` / `x/` word in a tree block, with the top-level entry it belongs to."""
    top = None
    for line in block.split("\n"):
        m = re.match(r"  (\S+)", line)
        if m and not line.startswith("   "):
            top = m.group(1)
            if top.startswith(base.name + "/"):
                top = top[len(base.name) + 1:]
        if top is None:
            continue
        rest = line[len(m.group(0)):] if m and not line.startswith("   ") else line
        # Words ending .rs, or lowercase folder names ending / (prose such as Mat3/Vec3,
        # TU/TR or processorN/ is not a path of the tree).
        for word in re.findall(r"(?<![\w:/.*])((?:[a-z_]\w*/)*[a-z_]\w*\.rs|(?:[a-z_*][a-z_0-9*]*/)+)(?![\w/])", rest):
            yield top, word


def exists_under(base, top, word):
    if (ROOT / word).exists() or any(base.rglob(word.rstrip("/"))):
        return True
    start = base / top.rstrip("/") if top.endswith("/") else base
    if top.endswith(".rs") and word == top:
        return (base / top).exists() or any(base.rglob(top))
    if not start.exists():
        return False
    if "*" in word:
        return True
    name = word.rstrip("/")
    want_dir = word.endswith("/")
    if (start / name).exists():
        return True
    return any(p.is_dir() == want_dir for p in start.rglob(name))


for block in blocks:
    first = block.strip().split("\n")[0].strip()
    if first not in ("src/", "tests/"):
        continue
    base = ROOT / first.rstrip("/")
    for top, word in tree_names(block, base):
        if word in ("python/", "src/", "tests/") or word.startswith(("python/", "pseudorigid/")):
            continue
        if top in ("python/", "theory,"):
            continue
        if not exists_under(base, top, word):
            fail(arch, f"names {word} under {first}{top}, which is not in the tree")
        elif VERBOSE:
            print(f"  ok ARCHITECTURE.md: {first}{top} {word}")

# ... and the test list is complete: every test module file of tests/ (and every module file
# of src/) is named in its tree.
for block in blocks:
    first = block.strip().split("\n")[0].strip()
    if first not in ("src/", "tests/"):
        continue
    words = set(re.findall(r"\w+", block))
    for rs in sorted((ROOT / first).rglob("*.rs")):
        if rs.stem in ("mod", "main", "lib") or "data" in rs.relative_to(ROOT / first).parts[:1]:
            continue
        if rs.stem not in words:
            fail(arch, f"its {first} tree does not name {rs.relative_to(ROOT)}")

# python/ as ARCHITECTURE.md describes it
for block in blocks:
    m = re.search(r"^python/(.*?)(?=^\S|\Z)", block, flags=re.S | re.M)
    if not m:
        continue
    for word in re.findall(r"\b(\w+\.rs)\b", m.group(0)):
        if not (ROOT / "python" / "src" / word).exists():
            fail(arch, f"names python/src/{word}, which is not in the tree")
    for word in re.findall(r"\b(\w+)/:", m.group(0)):
        if not (ROOT / "python" / word).is_dir():
            fail(arch, f"names python/{word}/, which is not in the tree")
    layers = re.search(r"bindings\s+over\s+(.*?)\s+only", m.group(0), flags=re.S)
    if layers:
        modules = {q.stem for q in (ROOT / "src").iterdir()}
        named = set(re.findall(r"[a-z_]+", layers.group(1))) & modules
        used = set()
        for rs in (ROOT / "python" / "src").glob("*.rs"):
            used |= set(re.findall(r"pseudorigid::([a-z_]+)", rs.read_text()))
        if used - named:
            fail(arch, f"says the Python bindings use only {sorted(named)}; python/src also "
                       f"uses {sorted(used - named)}")


def resolve_module(parts, base):
    """The file of module path `parts` under base, and the parts left over (items)."""
    here = base
    for k, part in enumerate(parts):
        if (here / f"{part}.rs").is_file():
            if k + 1 < len(parts) and (here / part).is_dir():
                here = here / part
                continue
            return here / f"{part}.rs", parts[k + 1:]
        if (here / part / "mod.rs").is_file():
            if k + 1 == len(parts):
                return here / part / "mod.rs", []
            here = here / part
            continue
        if k == 0:
            return None, parts
        mod = here / "mod.rs"
        return (mod if mod.is_file() else None), parts[k:]
    return None, []


DEFINES = r"(?:fn|struct|enum|trait|mod|const|type|static|macro_rules!)\s+{}\b|\b{}\s*[\(\{{,]"
src_top = {p.stem for p in (ROOT / "src").iterdir()}
for path in sorted(set(re.findall(r"`([a-z_]+(?:::[A-Za-z_0-9]+)+)", text))):
    parts = path.split("::")
    if parts[0] not in src_top:
        continue
    file, items = resolve_module(parts, ROOT / "src")
    if file is None:
        fail(arch, f"names `{path}`, which is no module of src/")
        continue
    if items:
        body = file.read_text()
        folder = file.parent if file.name == "mod.rs" else file.with_suffix("")
        bodies = [body] + ([q.read_text() for q in folder.rglob("*.rs")] if folder.is_dir() else [])
        if not any(re.search(DEFINES.format(items[0], items[0]), b) for b in bodies):
            fail(arch, f"names `{path}`: {file.relative_to(ROOT)} defines no {items[0]}")
            continue
    if VERBOSE:
        print(f"  ok ARCHITECTURE.md: `{path}` in {file.relative_to(ROOT)}")

for doc in (arch, readme):
    for path in re.findall(r"cargo test --test suite ([a-z_:]+)", doc.read_text()):
        file, items = resolve_module(path.split("::"), ROOT / "tests" / "suite")
        if file is None or items:
            fail(doc, f"runs `cargo test --test suite {path}`: no such test module in tests/suite")

# ---------------------------------------------------------------------------------------------

total = sum(counts.values())
if errors:
    print("check-numbers: FAILED", file=sys.stderr)
    for e in errors:
        print("  " + e, file=sys.stderr)
    sys.exit(1)
print(f"check-numbers: {total} quoted numbers in {len(counts)} files match their CSVs; "
      f"ARCHITECTURE.md matches the tree")
