#!/usr/bin/env bash
# Checks one figure of scripts/run_real_evaluation.sh's results.tsv against the issue's target.
#
#   check_real_results.sh DATA RESULTS.tsv recordings        every recording has its figures
#   check_real_results.sh DATA RESULTS.tsv walls_kept NAME   walls kept >= 98 %
#   check_real_results.sh DATA RESULTS.tsv no_glass NAME     no cell drawn glass or metal
#   check_real_results.sh DATA RESULTS.tsv people_left NAME  people left <= the plain grid's
# and the same of the node's map at the end of a replay: walls_kept_live, no_glass_live,
# people_left_live.
# Exits 77 (skipped) when DATA/real is absent.
set -euo pipefail
data="$1" results="$2" check="$3" arg="${4:-}"
if [[ ! -d "$data/real" ]]; then
  echo "skipped: no $data/real (the recordings of ../shared/data)"
  exit 77
fi
[[ -f "$results" ]] || { echo "no $results: real_data_convert_and_map did not run" >&2; exit 1; }

field() {  # field NAME COLUMN: fails when either is missing (an unknown column is not $0)
  awk -F'\t' -v name="$1" -v column="$2" '
    NR == 1 { for (i = 1; i <= NF; ++i) index_of[$i] = i; if (!(column in index_of)) exit 1; next }
    $1 == name { print $(index_of[column]); found = 1 }
    END { if (!found) exit 1 }' "$results"
}

# A check ending in _live reads the columns of the node's map at the end of a replay.
map=RFM source=rfm walls_column=walls_kept_percent
if [[ "$check" == *_live ]]; then
  map="the node's map" source=live walls_column=live_walls_kept_percent check="${check%_live}"
fi

case "$check" in
  recordings)
    expected=$( (ls "$data"/real/*.log.gz; ls "$data"/real/*.bag) 2> /dev/null |
      xargs -n1 basename | sed 's/\.log\.gz$//; s/\.bag$//' | sort)
    status=0
    for name in $expected; do
      kept=$(field "$name" walls_kept_percent) || { echo "$name: no figures"; status=1; continue; }
      if [[ ! "$kept" =~ ^[0-9]+(\.[0-9]+)?$ ]]; then echo "$name: walls kept '$kept'"; status=1; fi
      echo "$name: converted, mapped twice and measured (walls kept $kept %)"
    done
    exit $status
    ;;
  walls_kept)
    kept=$(field "$arg" "$walls_column")
    echo "$arg: walls kept $kept % in $map (target >= 98 %)"
    awk -v k="$kept" 'BEGIN { exit !(k >= 98.0) }'
    ;;
  no_glass)
    glass=$(field "$arg" "${source}_glass") metal=$(field "$arg" "${source}_metal")
    echo "$arg: $map draws $glass cells glass and $metal metal in a room without either (target 0)"
    [[ "$glass" == 0 && "$metal" == 0 ]]
    ;;
  people_left)
    rfm=$(field "$arg" "people_left_$source") plain=$(field "$arg" people_left_plain)
    echo "$arg: people left: $map $rfm cells, plain grid $plain (target: no more than the plain grid)"
    [[ "$rfm" =~ ^[0-9]+$ && "$plain" =~ ^[0-9]+$ ]] && ((rfm <= plain))
    ;;
  *)
    echo "unknown check $check" >&2
    exit 2
    ;;
esac
