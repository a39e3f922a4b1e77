#!/usr/bin/env bash
# Regenerates doc/real_data.md and its pictures doc/real_data/*.png: every CARMEN log of
# ../shared/data/real is converted with rfm_carmen2bag, every recording is mapped twice with
# rfm_offline (default parameters, then --baseline: the plain occupancy grid) and once as the
# node maps it (rfm_live_labels --map-out), and the maps are measured with rfm_compare_maps (walls
# kept, what the RFM made of the walls it dropped, glass and metal found) and, on the stationary
# recording, rfm_people_left (people left in each map).
#
#   scripts/run_real_evaluation.sh
#
# Environment:
#   DATA      the data directory (default: ../shared/data beside the checkout)
#   OUT       scratch directory for bags, maps and results.tsv (default: /tmp/rfm_real)
#   REPORT    the report (default: doc/real_data.md in the checkout)
#   PICTURES  its pictures (default: doc/real_data in the checkout)
#   JOBS      recordings mapped at once (default: 2)
#   SOURCE    where DATA's recordings come from, a sentence for the report (default: the
#             description of ../shared/data/real)
#   RFM_BIN   directory holding the built tools (default: rosrun from the workspace RFM_WS,
#             by default rfm_ws beside the checkout)
# OUT/results.tsv holds the figures, one recording a line, for test/real's checks.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
REPO="$rfm_source_dir"
DATA="${DATA:-$rfm_shared_data}"
OUT="${OUT:-/tmp/rfm_real}"
REPORT="${REPORT:-$REPO/doc/real_data.md}"
PICTURES="${PICTURES:-$REPO/doc/real_data}"
JOBS="${JOBS:-2}"
STATIONARY=demo_stationary_simple_environment
SOURCE="${SOURCE:-The recordings are those of \`../shared/data/real\` (see its README.md): CARMEN
logs of static buildings with a few people, and a stationary lidar in a room without glass while
people walk past.}"

tool() {
  if [[ -n "${RFM_BIN:-}" ]]; then
    "$RFM_BIN/$1" "${@:2}"
  else
    rosrun reflectance_field_map "$@"
  fi
}

# Converts (a CARMEN log) and maps one recording: OUT/NAME/{rfm,plain,live}, compare.txt,
# live_compare.txt and the picture, and for the stationary recording people_left.txt.
map_recording() {
  local name="$1" dir="$OUT/$1"
  rm -rf "$dir" && mkdir -p "$dir"
  local bag flags=()
  if [[ "$name" == "$STATIONARY" ]]; then
    bag="$DATA/real/$name.bag"
    flags=(--fixed-frame laser --scan-topics /scan)
  else
    bag="$dir/$name.bag"
    tool rfm_carmen2bag "$DATA/real/$name.log.gz" "$bag" > "$dir/convert.txt" 2>&1 ||
      { cat "$dir/convert.txt" >&2; echo "$name: conversion failed" >&2; return 1; }
    flags=(--scan-topics /scan)
  fi
  tool rfm_offline --bag "$bag" --out "$dir/rfm" "${flags[@]}" > "$dir/rfm.txt" 2>&1 ||
    { tail -5 "$dir/rfm.txt" >&2; echo "$name: rfm_offline failed" >&2; return 1; }
  tool rfm_offline --baseline --bag "$bag" --out "$dir/plain" "${flags[@]}" > "$dir/plain.txt" 2>&1 ||
    { tail -5 "$dir/plain.txt" >&2; echo "$name: rfm_offline --baseline failed" >&2; return 1; }
  tool rfm_compare_maps "$dir/rfm" "$dir/plain" --picture "$PICTURES/$name.png" > "$dir/compare.txt"
  # The map the node holds at the end of a replay: each scan added as it arrives, a pass every
  # 0.5 s of the scans' clock and one when they stop.
  tool rfm_live_labels "$bag" "$dir/live_labels.bag" "${flags[@]}" --map-out "$dir/live" \
    > "$dir/live.txt" 2>&1 ||
    { tail -5 "$dir/live.txt" >&2; echo "$name: rfm_live_labels failed" >&2; return 1; }
  rm -f "$dir/live_labels.bag"
  tool rfm_compare_maps "$dir/live" "$dir/plain" > "$dir/live_compare.txt"
  if [[ "$name" == "$STATIONARY" ]]; then
    tool rfm_people_left --bag "$bag" "${flags[@]}" "$dir/rfm" "$dir/plain" \
      --picture "$PICTURES/${name}_people_left.png" > "$dir/people_left.txt" 2> /dev/null
    tool rfm_people_left --bag "$bag" "${flags[@]}" "$dir/live" > "$dir/people_left_live.txt" \
      2> /dev/null
    for margin in 0 1 3; do
      tool rfm_people_left --margin "$margin" --bag "$bag" "${flags[@]}" "$dir/rfm" "$dir/plain" \
        > "$dir/people_left_margin$margin.txt" 2> /dev/null
    done
  fi
  [[ "$name" != "$STATIONARY" ]] && rm -f "$bag"  # bags are large; the maps stay
  echo "== $name: $(awk '$1 == "walls_kept_percent" {print $2}' "$dir/compare.txt") % walls kept"
}

if [[ "${1:-}" == --one ]]; then  # a worker of the loop below
  map_recording "$2"
  exit
fi

if [[ ! -d "$DATA/real" ]]; then
  echo "run_real_evaluation.sh: no $DATA/real (set DATA)" >&2
  exit 77
fi
if [[ -z "${RFM_BIN:-}" ]]; then
  [[ -f "$rfm_ws/devel/setup.bash" ]] ||
    { echo "run_real_evaluation.sh: build $rfm_ws first or set RFM_BIN" >&2; exit 1; }
  rfm_activate
fi
export DATA OUT PICTURES RFM_BIN ROS_PACKAGE_PATH="${ROS_PACKAGE_PATH:-}"
mkdir -p "$OUT" "$PICTURES" "$(dirname "$REPORT")"

# The longest first, so the jobs end together.
names=()
for log in $(ls -S "$DATA"/real/*.log.gz); do names+=("$(basename "$log" .log.gz)"); done
[[ -f "$DATA/real/$STATIONARY.bag" ]] && names+=("$STATIONARY")
start=$(date +%s)
printf '%s\n' "${names[@]}" | xargs -P "$JOBS" -I{} bash "${BASH_SOURCE[0]}" --one {}
seconds=$(($(date +%s) - start))

value() { awk -v k="$2" '$1 == k {print $2}' "$OUT/$1/${3:-compare.txt}"; }  # NAME KEY [FILE]
live() { value "$1" "$2" live_compare.txt; }
people() { awk -v d="$OUT/$1/$2" '$2 == d {print $6}' "$OUT/$1/${3:-people_left.txt}"; }
occupied() { awk -v d="$OUT/$1/$2" '$2 == d {print $4}' "$OUT/$1/people_left.txt"; }

# results.tsv: one recording a line.
{
  printf 'recording\twalls_kept_percent\tplain_occupied\tkept\tdropped_motion\tdropped_free'
  printf '\tdropped_unknown\trfm_static\trfm_glass\trfm_metal\tpeople_left_rfm\tpeople_left_plain'
  printf '\tlive_walls_kept_percent\tlive_glass\tlive_metal\tpeople_left_live\n'
  for name in $(printf '%s\n' "${names[@]}" | sort); do
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s' "$name" "$(value "$name" walls_kept_percent)" \
      "$(value "$name" plain_occupied)" "$(value "$name" kept)" "$(value "$name" dropped_motion)" \
      "$(value "$name" dropped_free)" "$(value "$name" dropped_unknown)" \
      "$(value "$name" rfm_static)" "$(value "$name" rfm_glass)" "$(value "$name" rfm_metal)"
    if [[ "$name" == "$STATIONARY" ]]; then
      printf '\t%s\t%s' "$(people "$name" rfm)" "$(people "$name" plain)"
    else
      printf '\t-\t-'
    fi
    printf '\t%s\t%s\t%s' "$(live "$name" walls_kept_percent)" "$(live "$name" rfm_glass)" \
      "$(live "$name" rfm_metal)"
    if [[ "$name" == "$STATIONARY" ]]; then
      printf '\t%s\n' "$(people "$name" live people_left_live.txt)"
    else
      printf '\t-\n'
    fi
  done
} > "$OUT/results.tsv"

# The report.
commit="$(git -C "$REPO" rev-parse --short HEAD 2>/dev/null || echo unknown)"
# The tools the report runs are built from src and include, rfm_live_labels from test/benchmark.
if [[ -n "$(git -C "$REPO" status --porcelain -- src include test/benchmark 2>/dev/null)" ]]; then
  commit="$commit + uncommitted changes"
fi
pictures_rel="$(realpath --relative-to="$(dirname "$REPORT")" "$PICTURES")"
stationary_row=""
glass_where=""  # looked at in the pictures of ../shared/data's recordings only
[[ "$DATA" == "$rfm_shared_data" ]] && glass_where="; in the
pictures most lie on furniture and clutter in rooms"
if [[ " ${names[*]} " == *" $STATIONARY "* ]]; then
  stationary_row=" The stationary recording's row is given for completeness:
its plain grid holds the people who walked past (see its section), so 98 % is no target there."
fi
clock_of() {
  awk '/^wrote / {gsub(/[()]/, ""); print $(NF - 1)}' "$OUT/$1/convert.txt"
}
{
  cat << EOF
# Real recordings: walls kept, glass and metal, people left

Generated by \`scripts/run_real_evaluation.sh\` at $commit ($(date -u +%Y-%m-%d), ${seconds} s with
JOBS=$JOBS).
$(rfm_wrap "$SOURCE")
Each log is converted with \`rfm_carmen2bag\` (doc/carmen.md) and every recording is mapped twice
with \`rfm_offline\`: default parameters (the RFM), then \`--baseline\` (the plain occupancy grid:
the same rays, no directions, no classes).

## Walls kept

*Walls kept* is the share of the plain grid's occupied cells that the RFM also has occupied
(\`map.pgm\`) within one cell (Chebyshev distance 1). These recordings are static buildings with
a few people, so nearly all of the plain grid's occupied cells are walls: the target is 98 % or
more on every recording (stretch 99.5 %). A dropped cell is counted by what the RFM made of it
(\`classes.pgm\` at that cell): *motion* is free space in \`/rfm/map\` (a navigation stack would
drive through it), *free* is what the RFM's evidence there says, *unknown* was never decided.
The next columns count the RFM map's cells drawn static, glass and metal. None of these
buildings has glass annotated. *Walls kept, live* is the same measure for the map the node holds
at the end of a replay of the recording (\`rfm_live_labels --map-out\`: each scan added as it
arrives, a motion-removal pass every 0.5 s of the scans' clock and one when they stop), against
the same plain grid.$stationary_row

| recording | scans | clock | plain occupied | walls kept | dropped: motion | free | unknown | static | glass | metal | walls kept, live |
|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|
EOF
  for name in $(printf '%s\n' "${names[@]}" | sort); do
    if [[ "$name" == "$STATIONARY" ]]; then clock=bag; file="$name.bag"; else
      clock="$(clock_of "$name")"; file="$name.log.gz"; fi
    n="$(awk '/^read / {print $2; exit}' "$OUT/$name/rfm.txt")"
    printf '| %s | %s | %s | %s | **%s %%** | %s | %s | %s | %s | %s | %s | %s %% |\n' "$file" "$n" \
      "$clock" "$(value "$name" plain_occupied)" "$(value "$name" walls_kept_percent)" \
      "$(value "$name" dropped_motion)" "$(value "$name" dropped_free)" \
      "$(value "$name" dropped_unknown)" "$(value "$name" rfm_static)" \
      "$(value "$name" rfm_glass)" "$(value "$name" rfm_metal)" "$(live "$name" walls_kept_percent)"
  done
  cat << EOF
EOF
  # What the table says, counted from it.
  logs=0 no_static=0 dropped=0 dropped_motion=0
  for name in "${names[@]}"; do
    [[ "$name" == "$STATIONARY" ]] && continue
    logs=$((logs + 1))
    [[ "$(value "$name" rfm_static)" == 0 ]] && no_static=$((no_static + 1))
    dropped=$((dropped + $(value "$name" dropped)))
    dropped_motion=$((dropped_motion + $(value "$name" dropped_motion)))
  done
  cat << EOF

Over the $logs logs the RFM drops $dropped of the plain grid's wall cells, $dropped_motion of them
as motion. Logs on which it draws no cell static (every obstacle it keeps is glass or metal):
$no_static of $logs.

A dropped cell *unknown* holds no evidence in the RFM: rays that passed through glass on a pane
(a thin straight line of obstacle cells, doc/design.md) lose all they saw beyond it (Alg. 3), so
what a window shows outside, or what a wall face or doorway wrongly found glass hides, stays
unknown (\`--no-reflection-removal\` keeps it). Returns from clutter seen narrowly, off any
such line, are drawn static and cut no ray. *Motion* is
evidence later seen through: people, and chairs and clutter moved or seen from few places.
None of these buildings has glass annotated, so the glass cells cannot be scored here$glass_where.
The random scenes (doc/random_evaluation.md) score glass where the truth is known.

*clock*: the converter's clock, \`ipc_timestamp\` (the log's stamps, repaired where they step
back) or \`synthetic\` (stamps all equal: one scan every so often in file order, from the path;
\`convert.txt\` of each run says what was done).

## Pictures

Each picture shows the RFM (left) and the plain grid (right) over the same area, one pixel for
a few cells (a block shows its most telling cell). Left: static dark green, **glass blue**,
**metal red**, motion magenta, free near white, unknown grey: the blue and red cells are where
the RFM found glass and metal. Right: the plain grid's occupied cells black where the RFM kept
them, and coloured where it dropped them by what the RFM made of them: **motion magenta**,
**free orange**, **unknown teal**.

EOF
  for name in $(printf '%s\n' "${names[@]}" | sort); do
    k="$(value "$name" picture_cells_per_pixel)"
    printf '### %s\n\n![%s: RFM | plain grid](%s/%s.png)\n\n' "$name" "$name" "$pictures_rel" "$name"
    printf 'A pixel: %s x %s cells (%s cm). Walls kept %s %%; glass %s cells, metal %s.\n\n' "$k" \
      "$k" "$((k * 5))" "$(value "$name" walls_kept_percent)" "$(value "$name" rfm_glass)" \
      "$(value "$name" rfm_metal)"
  done
  if [[ " ${names[*]} " == *" $STATIONARY "* ]]; then
    s=$STATIONARY
    glass="$(value $s rfm_glass)"
    metal="$(value $s rfm_metal)"
    cat << EOF
## The stationary recording: glass drawn and people left

\`$s.bag\`: a lidar that does not move (512 beams over 180 deg,
5.6 m, 10 Hz, 1265 scans) in a room without glass, people walking past it; mapped with \`--fixed-frame laser
--scan-topics /scan\` (the bag has no TF).

**Glass drawn.** The room has no glass and no metal, so every cell the RFM draws glass or metal
there is a wall (or furniture) drawn as glass or metal: the target is none.

**People left** is the number of a map's occupied cells that the recording's scans saw through
more often than they hit them. A scan *hits* a cell when one of its beams returns from it, and
*sees through* it when none does and one crosses it and returns from more than two cells (10 cm)
beyond it. Each scan counts once per cell.

Why this measures people: the sensor does not move, so every cell is observed by the same beams
all recording long. A wall is hit whenever it is observed; nothing returns from behind it. A
cell where a person stood or walked is hit only while they were there and is seen through the
rest of the time, by returns from the wall behind. So an occupied cell that most scans saw
through is an obstacle that was not there most of the time: a person left in the map. The
measure needs no annotation and does not depend on the mapper: the same scans judge both maps.
Its choices:
- Only returns count as seeing through. A beam without a return may have met nothing, but it
  may also have dropped out on a far or dark wall: this room's far walls, near the 5.6 m range,
  return only now and then, and counting their no-return beams as sight through would call them
  people. So an obstacle with nothing within range behind it cannot be judged and counts as
  structure: the measure is a lower bound on the people left, the same for both maps.
- The two-cell margin: range noise moves a wall's return across a cell boundary, so a beam that
  returns from the next cell or the one after has not shown that the cell is empty. Without the
  margin, wall cells are counted (the margin 0 column below).
- A person who stood still for more than half of the recording is structure by this measure.

The target: the RFM leaves no more people than the plain grid.

| map | occupied cells | people left | glass cells | metal cells |
|---|---:|---:|---:|---:|
| RFM (defaults) | $(occupied $s rfm) | **$(people $s rfm)** | **$glass** | **$metal** |
| RFM, live (the node's map at the end of a replay) | $(awk '{print $4}' "$OUT/$s/people_left_live.txt") | **$(people $s live people_left_live.txt)** | **$(live $s rfm_glass)** | **$(live $s rfm_metal)** |
| plain grid (\`--baseline\`) | $(occupied $s plain) | **$(people $s plain)** | - | - |

The measure with other margins (cells beyond the cell a return must come from):

| margin | 0 | 1 | **2** | 3 |
|---|---:|---:|---:|---:|
| RFM | $(people $s rfm people_left_margin0.txt) | $(people $s rfm people_left_margin1.txt) | $(people $s rfm) | $(people $s rfm people_left_margin3.txt) |
| plain grid | $(people $s plain people_left_margin0.txt) | $(people $s plain people_left_margin1.txt) | $(people $s plain) | $(people $s plain people_left_margin3.txt) |

![people left: RFM | plain grid](${pictures_rel}/${s}_people_left.png)

Occupied cells of each map (RFM left, plain grid right, 3 pixels a cell): black, or **red**
where people were left (seen through by most scans). The RFM's few red cells lie on the edges
of walls; the plain grid's include people left in the middle of the room. The plain grid's
scattered cells at the bottom right lie near the range limit with nothing in range behind them:
only a few of them can be judged (those in red).

EOF
  fi
  if [[ "$DATA" != "$rfm_shared_data" ]]; then
    cat << EOF
## Reproduce

With the logs in \`DIR/real\`:

    DATA=DIR SOURCE="..." REPORT=$(realpath --relative-to="$REPO" "$REPORT") \\
      PICTURES=$(realpath --relative-to="$REPO" "$PICTURES") scripts/run_real_evaluation.sh
EOF
  else
    cat << EOF
## Reproduce

    scripts/run_real_evaluation.sh              # JOBS=2 DATA=../shared/data OUT=/tmp/rfm_real
    # one recording by hand:
    rosrun reflectance_field_map rfm_carmen2bag ../shared/data/real/intel-corrected.log.gz /tmp/intel.bag
    rosrun reflectance_field_map rfm_offline --bag /tmp/intel.bag --out /tmp/intel/rfm --scan-topics /scan
    rosrun reflectance_field_map rfm_offline --bag /tmp/intel.bag --out /tmp/intel/plain --scan-topics /scan --baseline
    rosrun reflectance_field_map rfm_compare_maps /tmp/intel/rfm /tmp/intel/plain --picture /tmp/intel.png
    rosrun reflectance_field_map rfm_live_labels /tmp/intel.bag /tmp/intel/live_labels.bag --scan-topics /scan \\
        --map-out /tmp/intel/live
    rosrun reflectance_field_map rfm_compare_maps /tmp/intel/live /tmp/intel/plain
    rosrun reflectance_field_map rfm_people_left --bag ../shared/data/real/$STATIONARY.bag \\
        --scan-topics /scan --fixed-frame laser /tmp/stationary/rfm /tmp/stationary/plain

The checks of these figures run as ctest tests (\`test/real\`): walls kept >= 98 % on each log, no
glass or metal in the stationary room, people left no more than the plain grid's; for the
offline map and for the node's.
EOF
  fi
} > "$REPORT"
echo "wrote $REPORT, $PICTURES/*.png and $OUT/results.tsv (${seconds} s)"
