#!/bin/sh
# A user's own case on the defaults (issue: deposition you can trust on any mesh): mesh and
# solve the T-junction (cases/tjunction, blockMesh + simpleFoam, seconds), run its scene through
# the `pseudorigid` command, and check against OpenFOAM's own outlet flow rates: the tracers
# leave through the outlets in proportion to the outlet fluxes within three binomial standard
# errors, none fails, and at most 5 % are still inside after ten residence times. Those few are
# not hovering: tracers injected within tens of µm of the inlet's walls, or on the dividing
# streamline into the junction's far wall, creep along a no-slip wall; after 50 residence
# times 5 of 1 000 remain (34 after 10; the session note of this check).
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)
. "$repo/cases/install-openfoam.sh"
work="$repo/cases/tjunction/ci"
"$repo/cases/tjunction/Allrun" "$work"
cp "$repo/cases/tjunction/scene.toml" "$work/scene.toml"
cd "$repo"
cargo build --release --bin pseudorigid
target="${CARGO_TARGET_DIR:-$repo/target}"
"$target/release/pseudorigid" validate "$work/scene.toml"
"$target/release/pseudorigid" run --quiet --csv "$work/scene.toml" --out "$work/out"
python3 - "$work/flux.txt" "$work/out/results.csv" <<'PY'
import csv, math, sys
flux = dict(line.split() for line in open(sys.argv[1]) if line.strip())
q1, q2 = float(flux["outlet1"]), float(flux["outlet2"])
rows = list(csv.DictReader(open(sys.argv[2])))
fates = {}
for r in rows:
    key = (r["fate"], r["patch_name"])
    fates[key] = fates.get(key, 0) + 1
print("tjunction-ci: fates", fates)
n1 = fates.get(("escaped", "outlet1"), 0)
n2 = fates.get(("escaped", "outlet2"), 0)
failed = sum(v for k, v in fates.items() if k[0] == "failed")
suspended = sum(v for k, v in fates.items() if k[0] == "suspended")
expected = q1 / (q1 + q2)
n = n1 + n2
share = n1 / n if n else float("nan")
stderr = math.sqrt(expected * (1 - expected) / n) if n else float("nan")
print(f"tjunction-ci: outlet1 share {share:.4f} against the flux share {expected:.4f} (± {stderr:.4f}), {n} escaped of {len(rows)}")
if failed or suspended > 0.05 * len(rows) or not n or abs(share - expected) > 3 * stderr:
    sys.exit("tjunction-ci: FAILED")
PY
echo "tjunction-ci: OK"
