#!/usr/bin/env bash
# Record what every bundled example gives through every command that reads it, into DIR.
# Used to check that a restructuring changes no number: record before and after, then
#   python tools/compare_outputs.py BEFORE AFTER   (CSV/JSON compared by column name to 1e-9).
set -u
out=${1:?usage: tools/record_outputs.sh DIR}
lw=${LINKWORK:-.venv/bin/linkwork}  # may be a command with words, e.g. "env PYTHONPATH=$PWD .venv/bin/linkwork"
mkdir -p "$out"
run() { # name, args...
  local name=$1; shift
  $lw "$@" --out "$out/$name" > "$out/$name.stdout" 2> "$out/$name.stderr"
  echo $? > "$out/$name.rc"
}
for f in examples/*.toml tests/data/*.toml; do
  b=$(basename "$f" .toml)
  t=$(sed -n 's/^type *= *"\(.*\)".*/\1/p' "$f" | head -1)
  case "$t" in
    swashplate) run "swashplate-analyze-$b" swashplate analyze "$f" ;;
    synthesis)
      for k in path function motion; do
        if grep -q "^\[$k\]" "$f"; then run "synthesize-$k-$b" synthesize "$k" "$f"; fi
      done ;;
    *) run "analyze-$b" analyze "$f" ;;
  esac
  if grep -q '^\[drive\]' "$f"; then
    run "dynamics-$b" dynamics "$f"
  fi
  if [ "$t" = planar ]; then
    run "balance-$b" balance "$f"
    run "balance-pareto-$b" balance "$f" --pareto
    run "reactions-$b" reactions "$f" --no-plots
    run "reactions-disp-$b" reactions "$f" --no-plots --method displacement
    run "reactions-tol-$b" reactions "$f" --no-plots --tolerance-study 500 --seed 3
  fi
done
run swashplate-synth-1 swashplate synthesize -R "100 mm" -H "60 mm" --delta "10 deg" --candidates 2048
run swashplate-synth-4a swashplate synthesize -R "100 mm" -H "60 mm" --scheme 4a --objective torque --candidates 2048
