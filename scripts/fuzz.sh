#!/usr/bin/env bash
# Fuzzes foon-core with cargo-fuzz (libFuzzer): seeds each target's corpus from the real FOON
# data beside the repository, then runs the targets one after another, one job each, for
# SECONDS each (default 600), and writes a summary.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]   targets: foon_text objects rates utensils foon_graph
#
# Environment: FOON_DATA (default ../shared/data/foon beside the repository),
# FUZZ_SANITIZER (default none: foon-core forbids unsafe code; "address" halves the speed),
# FUZZ_MAX_LEN (default 4096), FUZZ_RSS_MB (default 2048), FUZZ_PARALLEL=1 (run the
# targets at once, one core each, instead of one after another).
# cargo-fuzz needs nightly flags; the stable toolchain accepts them with RUSTC_BOOTSTRAP=1.
# Crashes land in rust/foon-core/fuzz/artifacts/<target>/, logs and the summary in
# rust/foon-core/fuzz/artifacts/logs/ (both git-ignored, as is the corpus).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
FUZZ="$ROOT/rust/foon-core/fuzz"
DATA=${FOON_DATA:-"$ROOT/../shared/data/foon"}
SECS=${1:-600}
[[ $# -gt 0 ]] && shift
TARGETS=("$@")
[[ ${#TARGETS[@]} -eq 0 ]] && TARGETS=(foon_text objects rates utensils foon_graph)
SANITIZER=${FUZZ_SANITIZER:-none}
MAX_LEN=${FUZZ_MAX_LEN:-4096}
RSS_MB=${FUZZ_RSS_MB:-2048}
export RUSTC_BOOTSTRAP=1

if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "== installing cargo-fuzz"
    cargo install cargo-fuzz --locked
fi

echo "== seeding corpora from $DATA"
if [[ -d "$DATA" ]]; then
    python3 - "$DATA" "$FUZZ/corpus" "$MAX_LEN" <<'PY'
"""Seeds: small pieces of the real files (a few FUs, a few objects), so that every seed fits
in max_len and each dialect is represented. Never copies the data into the repository."""
import glob, json, os, sys

data, corpus, max_len = sys.argv[1], sys.argv[2], int(sys.argv[3])
count = {}

def put(target, name, blob):
    if not blob or len(blob) > max_len:
        return
    d = os.path.join(corpus, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "seed-" + name.replace("/", "_")), "wb") as fh:
        fh.write(blob)
    count[target] = count.get(target, 0) + 1

def fus(blob):
    """Splits FOON text into FUs (each ends with its '//' line), keeping bytes as they are."""
    out, cur = [], []
    for line in blob.splitlines(keepends=True):
        cur.append(line)
        if line.startswith(b"//"):
            out.append(b"".join(cur)); cur = []
    if cur:
        out.append(b"".join(cur))
    return out

def read(p):
    with open(p, "rb") as fh:
        return fh.read()

foon_files = ([os.path.join(data, "FOON.txt")]
              + sorted(glob.glob(os.path.join(data, "lab_history", "*FOON*.txt")))
              + sorted(glob.glob(os.path.join(data, "subgraphs_foon_api_FOON-111", "*.txt")))[:25]
              + sorted(glob.glob(os.path.join(data, "subgraphs_sakib_TXT", "*.txt")))[:25]
              + sorted(glob.glob(os.path.join(data, "subgraphs_misc", "*.txt"))))
for p in foon_files:
    if not os.path.isfile(p):
        continue
    units = fus(read(p))
    rel = os.path.relpath(p, data)
    for k, i in enumerate(range(0, min(len(units), 12), 3)):  # a few pieces of 3 FUs
        put("foon_text", f"{rel}.{k}", b"".join(units[i:i + 3]))
    if units:  # and the last FU alone (often unterminated or odd)
        put("foon_text", f"{rel}.last", units[-1])

def json_pieces(p, n=3):
    try:
        items = json.loads(read(p))
    except (ValueError, UnicodeDecodeError):
        return
    rel = os.path.relpath(p, data)
    if isinstance(items, list):
        for k, i in enumerate(range(0, min(len(items), 30), n)):
            put("objects", f"{rel}.{k}", json.dumps(items[i:i + n], indent=4).encode())
        if items:
            put("objects", f"{rel}.one", json.dumps(items[0]).encode())
    else:
        put("objects", rel, json.dumps(items).encode()[:max_len])

for p in ([os.path.join(data, n) for n in ("kitchen.json", "goal_nodes.json", "goal_nodes_25.json")]
          + sorted(glob.glob(os.path.join(data, "lab_history", "kitchen_*.json")))
          + sorted(glob.glob(os.path.join(data, "lab_info", "*.json")))
          + sorted(glob.glob(os.path.join(data, "lab_recipe_inputs", "*", "*.json")))[:10]):
    if os.path.isfile(p):
        json_pieces(p)
for p in sorted(glob.glob(os.path.join(data, "lab_history", "*ids_format*.txt"))):
    blob = read(p)
    lines = blob.splitlines(keepends=True)
    for k, i in enumerate(range(0, min(len(lines), 200), 40)):
        put("objects", f"{os.path.relpath(p, data)}.{k}", b"".join(lines[i:i + 40]))

for n in ("motion.txt", "motion_uniform_0.1.txt"):
    p = os.path.join(data, n)
    if os.path.isfile(p):
        put("rates", n, read(p))
for n in ("utensils.txt", "lab_info/default_ingredients.txt", "lab_info/dish_type.txt"):
    p = os.path.join(data, n)
    if os.path.isfile(p):
        blob = read(p)
        put("utensils", n, blob[:max_len])
print("   seeds:", ", ".join(f"{t} {c}" for t, c in sorted(count.items())))
PY
else
    echo "   (no data at $DATA: fuzzing from empty corpora)"
fi
for t in "${TARGETS[@]}"; do mkdir -p "$FUZZ/corpus/$t"; done

LOGS="$FUZZ/artifacts/logs"
mkdir -p "$LOGS"
SUMMARY="$LOGS/summary.md"
{
    echo "# fuzz run $(date -u +%Y-%m-%dT%H:%MZ), ${SECS}s per target, sanitizer $SANITIZER, max_len $MAX_LEN"
    echo
    echo "| target | status | runs | exec/s | cov | ft | corpus | crashes |"
    echo "|---|---|---|---|---|---|---|---|"
} > "$SUMMARY"

cd "$FUZZ"
echo "== building"
cargo fuzz build --sanitizer "$SANITIZER" 2>&1 | tail -3
fuzz_one() {  # runs one target, writes its summary row to $LOGS/$1.row
    local t=$1 log="$LOGS/$1.log" status=ok dict=()
    [[ -f "dicts/$t.dict" ]] && dict=("-dict=dicts/$t.dict")
    cargo fuzz run --sanitizer "$SANITIZER" "$t" "corpus/$t" -- \
        -max_total_time="$SECS" -max_len="$MAX_LEN" -rss_limit_mb="$RSS_MB" -timeout=20 \
        -print_final_stats=1 "${dict[@]}" > "$log" 2>&1 || status="FAILED"
    local runs speed last cov ft corp crashes
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
    speed=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
    last=$(grep -E '^#[0-9]+' "$log" | tail -1)
    cov=$(grep -o 'cov: [0-9]*' <<<"$last" | grep -o '[0-9]*' || true)
    ft=$(grep -o 'ft: [0-9]*' <<<"$last" | grep -o '[0-9]*' || true)
    corp=$(grep -o 'corp: [0-9]*/[0-9]*[a-zA-Z]*' <<<"$last" | sed 's/corp: //' || true)
    crashes=$(find "artifacts/$t" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'oom-*' -o -name 'timeout-*' -o -name 'slow-unit-*' \) 2>/dev/null | wc -l)
    echo "| $t | $status | ${runs:-?} | ${speed:-?} | ${cov:-?} | ${ft:-?} | ${corp:-?} | $crashes |" > "$LOGS/$t.row"
    tail -n 12 "$log"
    [[ $status == ok ]]
}

overall=0
if [[ ${FUZZ_PARALLEL:-0} == 1 ]]; then
    # All the targets at once, one core each.
    pids=()
    for t in "${TARGETS[@]}"; do
        echo "== $t: ${SECS}s (in parallel)"
        fuzz_one "$t" > "$LOGS/$t.tail" & pids+=($!)
    done
    for pid in "${pids[@]}"; do wait "$pid" || overall=1; done
    for t in "${TARGETS[@]}"; do cat "$LOGS/$t.tail"; done
else
    for t in "${TARGETS[@]}"; do
        echo "== $t: ${SECS}s"
        fuzz_one "$t" || overall=1
    done
fi
for t in "${TARGETS[@]}"; do cat "$LOGS/$t.row" >> "$SUMMARY"; done
echo
cat "$SUMMARY"
exit $overall
