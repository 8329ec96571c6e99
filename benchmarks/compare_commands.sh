#!/bin/bash
# Every command's output, before and after a change: stdout, stderr, exit status and the files it leaves, with
# times masked (wall_s and the other seconds, "in 0.03 s", progress lines, the wall_s column of --csv, the time
# column of a results table). Used for issue 34 item 3 (the commands moved into app/).
#
#   benchmarks/compare_commands.sh REF        # REF: the git ref of "before" (default main); after: this tree
#
# Each command line runs in a fresh folder holding a chain file, a reference netlist and two example scenes; a
# second part runs a sequence that shares stores (sweep, batch, then results in every form). Prints "same" or
# the difference for each line, and a count. Needs ngspice and gnucap, as the commands do.
set -u
ROOT=$(cd "$(dirname "$0")/.." && pwd)
REF=${1:-main}
PY=${PYTHON:-$ROOT/.venv/bin/python}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
mkdir -p "$WORK/base" "$WORK/fixtures"
git -C "$ROOT" archive "$REF" lcchain | tar -x -C "$WORK/base"
cp "$ROOT/netlists/perfect-N4.cir" "$WORK/fixtures/ref.cir"
cp "$ROOT/netlists/perfect-N4.cir" "$ROOT/lcchain/scenes/examples/cradle.toml" \
   "$ROOT/lcchain/scenes/examples/spectrum.toml" "$WORK/fixtures/"
printf '{"masses": [1, 1.5, 1, 1], "springs": [0, 1, 1, 1, 0]}' > "$WORK/fixtures/chain.json"

mask() { grep -v 'elapsed' | sed -E 's/[0-9]+\.[0-9]+ s\b/T s/g; s/\([0-9.]+ s\)/(T s)/g; s/in [0-9.]+ s/in T s/g; s/"[a-z_]*_s": [0-9.e+-]+/"X_s": T/g; s/"(ngspice|total|overhead_fraction|simulator_seconds|reference_seconds)": [0-9.e+-]+/"\1": T/g; s/ [0-9]+\.[0-9]{3} +$/ T/'; }
root_of() { if [ "$1" = base ]; then echo "$WORK/base"; else echo "$ROOT"; fi; }

n=0; bad=0
while IFS= read -r line; do
  [ -z "$line" ] && continue
  n=$((n + 1))
  for side in base after; do
    d=$WORK/run_$side; rm -rf "$d"; mkdir -p "$d"; cp "$WORK"/fixtures/* "$d"/
    (cd "$d" && PYTHONPATH=$(root_of $side) timeout 300 "$PY" -m lcchain $line > out 2> err; echo $? > rc)
    { mask < "$d/out"; echo "--- stderr"; mask < "$d/err"; echo "--- status $(cat "$d/rc")"; ls "$d"; } > "$WORK/$side.txt"
  done
  if cmp -s "$WORK/base.txt" "$WORK/after.txt"; then
    echo "same (status $(cat "$WORK/run_after/rc")): lcchain $line"
  else
    bad=$((bad + 1)); echo "DIFF: lcchain $line"; diff "$WORK/base.txt" "$WORK/after.txt" | head -8
  fi
done <<'CMDS'
design --case two-mass --N 7
design --case one-mass --N 1
design --case perfect --N 5 --json
design --case two-mass --N 5 --walls 2
table --case one-mass --N 3,4,5 --csv
table --case two-mass --N 3,,4
asymptotic --case one-mass
asymptotic --json
netlist --case two-mass --N 6 --Q 100
netlist --chain chain.json --coupling 0.1 -o out.cir
netlist --chain chain.json --N 5
netlist --case perfect --N 2
netlist --case two-mass --N 5 -o chain.json
examples
examples cradle
examples cradle -o -
reference-netlists --out refs
bom --case two-mass --N 6 --series E24 --tolerance 1%
bom --case two-mass --N 6 --csv
bom --case two-mass --N 6 --L0 -1
sensitivity --case two-mass --N 8 --top 4
sensitivity --case two-mass --N 8 --json --top 2
sensitivity --case two-mass --N 8 --top -1
sensitivity --case two-mass --N 8 --store x.sqlite
requirements --case two-mass --N 6 --check 0 --part coupling
requirements --case two-mass --N 6 --part nope
simulate --case two-mass --N 5 --json
simulate --case two-mass --N 5 --dt 0.05 --accuracy 1e-3
simulate --case two-mass --N 5 --engine ngspice,gnucap --plot x.png
simulate --case perfect --N 4 --netlist-out - --json
simulate --case two-mass --N 5 --waveform-out w.csv --netlist-out n.cir
spectrum --case two-mass --N 5 --json
spectrum --case two-mass --N 5 --z0 5
spectrum --case two-mass --N 5 --touchstone t.s2p --z0 75
run cradle.toml --json
run cradle.toml spectrum.toml --netlist-out x.cir
run nothere.toml
sweep --case two-mass --N 5,6 --store s.sqlite --executor serial --json
sweep --case two-mass --N 5 --vary a=1 --store s.sqlite
sweep --store s.sqlite --executor serial
batch ref.cir --store b.sqlite --executor serial --json
batch ref.cir --store b.sqlite --executor serial --strict
results nothere.sqlite
results s.sqlite --waveforms
check ref.cir --json
check ref.cir --accuracy 1e-12
doctor
CMDS

for side in base after; do
  d=$WORK/seq_$side; mkdir -p "$d"; cp "$WORK"/fixtures/* "$d"/
  while IFS= read -r line; do
    echo "### lcchain $line"
    (cd "$d" && PYTHONPATH=$(root_of $side) timeout 600 "$PY" -m lcchain $line 2>&1; echo "status $?")
  done <<'CMDS' | mask | sed -E 's/([0-9a-f]{64},[^,]*,)[0-9.e-]+/\1T/' > "$WORK/seq_$side.txt"
sweep --case two-mass,one-mass --N 5,6 --store s.sqlite --executor serial
sweep --case two-mass,one-mass --N 5,6 --store s.sqlite --executor serial
results s.sqlite
results s.sqlite --json
results s.sqlite --csv
results s.sqlite --summary
results s.sqlite --summary --csv
results s.sqlite --summary --json --metric energy
results s.sqlite --plot s.png
results s.sqlite --metric bogus --summary
batch ref.cir perfect-N4.cir --store b.sqlite --executor serial
results b.sqlite
results b.sqlite --csv
sweep cradle.toml --worst-case corners --store w.sqlite --executor serial
sweep --case two-mass --N 5 --tolerance 1% --samples 3 --store t.sqlite --executor serial --json
results t.sqlite --summary
sweep --case two-mass --N 5 --analysis ac --store a.sqlite --executor serial
results a.sqlite
CMDS
done
m=$(grep -c '^###' "$WORK/seq_after.txt")
if cmp -s "$WORK/seq_base.txt" "$WORK/seq_after.txt"; then
  echo "same: the sequence of $m command lines sharing stores"
else
  bad=$((bad + 1)); echo "DIFF: the sequence of $m command lines sharing stores"; diff "$WORK/seq_base.txt" "$WORK/seq_after.txt" | head -20
fi
echo "$n command lines and a sequence of $m: $bad differ (times masked)"
