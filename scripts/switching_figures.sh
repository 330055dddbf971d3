#!/usr/bin/env bash
# The figures and numbers of docs/switching.md (issue 12), from the repository root after a
# Release build:   bash scripts/switching_figures.sh [OUT]      (default OUT: out/switching)
#  - the hopping sieve (cases/sieve_1995_hopping.toml, e = 0.05 m) sampled every 20 us, and a
#    figure of u - u0 and R_u over its last three excitation periods, flights shaded;
#  - a sweep of e from 0.030 to 0.078 m with switching on and off (pcsim sweep), and a figure
#    of the contact fraction and the landing speed against e, with the onset e* where the paper's
#    steady-state verdict (min R_u > 0 over the window) first fails.
set -euo pipefail
OUT=${1:-out/switching}
PCSIM=${PCSIM:-build/pcsim}
mkdir -p "$OUT" docs/img

"$PCSIM" run cases/sieve_1995_hopping.toml --set output.dt=2e-5 --set output.summary_periods=3 \
  --out "$OUT/hop" > "$OUT/hop.txt"
"$PCSIM" sweep cases/sieve_1995_hopping.toml --vary parameters.e=0.030:0.078:49 --jobs 2 \
  --out "$OUT/sweep_switching" > /dev/null
"$PCSIM" sweep cases/sieve_1995.toml --vary parameters.e=0.030:0.078:49 --jobs 2 \
  --out "$OUT/sweep_paper" > /dev/null

# Column numbers by name.
col() { head -1 "$1" | tr ',' '\n' | grep -n -x "$2" | cut -d: -f1; }
TS="$OUT/hop/timeseries.csv"
W0=$(python3 -c "import json; print(json.load(open('$OUT/hop/summary.json'))['window'][0])")
W1=$(python3 -c "import json; print(json.load(open('$OUT/hop/summary.json'))['window'][1])")
U0=$(python3 -c "import json; print(json.load(open('$OUT/hop/summary.json'))['parameters']['u0'])")
CU=$(col "$TS" u); CR=$(col "$TS" R_u); CM=$(col "$TS" mode_contact)

SW="$OUT/sweep_switching/sweep.csv"; SP="$OUT/sweep_paper/sweep.csv"
CE=$(col "$SW" parameters.e)
CF=$(col "$SW" switching.contacts.contact.window.contact_fraction)
CV=$(col "$SW" switching.contacts.contact.window.max_impact_velocity)
CH=$(col "$SW" switching.contacts.contact.window.max_flight_height)
PE=$(col "$SP" parameters.e); PR=$(col "$SP" R_u_min)
# The onset: min R_u of the window (no switching) crosses zero, interpolated linearly.
ONSET=$(awk -F, -v e="$PE" -v r="$PR" 'NR > 1 && $r != "" { if (have && prev_r > 0 && $r <= 0) {
  printf "%.5f", prev_e + (0 - prev_r) * ($e - prev_e) / ($r - prev_r); exit } prev_e = $e; prev_r = $r; have = 1 }' "$SP")
echo "onset of lift-off (min R_u = 0 in the steady state): e* = $ONSET m"

# The flights of the window as rectangles (from events.csv: a flight runs from the switch into
# "flight" to the next switch of the contact).
RECTS=$(awk -F, -v w0="$W0" -v w1="$W1" 'NR > 1 && $3 == "contact" {
  if ($5 == "flight" && !open) { a = $1; open = 1 } else if ($5 != "flight" && open) {
    if ($1 > w0 && a < w1) printf "set object rect from %s, graph 0 to %s, graph 1 fc rgb \"#a6c8f4\" fs solid 0.5 noborder behind\n", (a > w0 ? a : w0), $1
    open = 0 } }' "$OUT/hop/events.csv")

gnuplot <<GP
set terminal pngcairo size 1000,700 font 'sans,10' noenhanced
set datafile separator ','
set output 'docs/img/switching_sieve_hopping.png'
set multiplot layout 2,1 title 'Vibration sieve, e = 0.05 m: the roller hops once per excitation period (shaded: flight)'
set xrange [$W0:$W1]
set grid
set xlabel 't [s]'
$RECTS
set ylabel 'u - u0 [micrometres]'
plot '$TS' every ::1 using 1:((\$$CU - $U0)*1e6) with lines lw 2 lc rgb '#5020a0' title 'u - u0 (the gap; shaded: flight)'
set ylabel 'R_u [N]'
plot '$TS' every ::1 using 1:$CR with lines lw 2 lc rgb '#b03030' title 'R_u (the normal force on the roller)', \
     0 with lines dt 2 lc rgb 'black' notitle
unset multiplot
unset object

set output 'docs/img/switching_sieve_sweep_e.png'
set multiplot layout 2,1 title 'Vibration sieve: contact lost above e* = $ONSET m (the steady-state verdict (3.1), min R_u > 0, fails there)'
unset xrange
set xrange [0.03:0.078]
set ylabel 'contact fraction, min R_u/(m2 g)'
set xlabel 'eccentricity e [m]'
set yrange [-0.1:1.1]
set arrow 1 from $ONSET, graph 0 to $ONSET, graph 1 nohead dt 2 lc rgb 'red'
plot '$SW' every ::1 using $CE:$CF with linespoints pt 7 ps 0.6 lw 2 title 'contact fraction (switching)', \
     '$SP' every ::1 using $PE:(\$$PR/(0.5*9.81)) with linespoints pt 6 ps 0.6 title 'min R_u/(m2 g), steady state, no switching (paper)', \
     0 with lines lc rgb 'black' notitle
set yrange [*:*]
set ylabel 'landing speed [mm/s], hop height [um]'
plot '$SW' every ::1 using $CE:(\$$CV*1e3) with linespoints pt 7 ps 0.6 lw 2 title 'landing speed (max over the window)', \
     '' every ::1 using $CE:(\$$CH*1e6) with linespoints pt 5 ps 0.6 title 'hop height (max over the window)'
unset multiplot
GP
echo "wrote docs/img/switching_sieve_hopping.png docs/img/switching_sieve_sweep_e.png"
