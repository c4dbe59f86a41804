# Section "numerics" of the third audit (issue 35): the solvers' stopping tests and limits.

# ---- fixtures: the cube hexapod with its gauge's noise stated, and the same with the stated
# noise multiplied by 1e8 and 1e-8 (a common scale of every weight: the same minimum) ---------
"$kincal" model --out plain.json >/dev/null
/usr/bin/python3 - <<'PY'
import json
m = json.load(open("plain.json"))
for name, factor in (("M", 1.0), ("Mbig", 1e8), ("Msmall", 1e-8)):
    m["reading_std"] = {"gauge": 0.0125 / 3 ** 0.5 * factor}
    json.dump(m, open(name + ".json", "w"), indent=2)
PY
"$kincal" simulate --model M.json --poses 60 --noise-half-width 0.0125 --seed 5 --validation 1 \
  --write-data D.csv >/dev/null 2>&1 || { echo "FAILED: fixture simulate"; exit 1; }

# same_fit DESCRIPTION REFERENCE.json OTHER.json: both converged, after at least one iteration,
# at the same estimate (1e-3 mm: the data determine these parameters to ~1 mm, and the stopping
# tests leave ~1e-4 mm in this flat valley) with the same residual RMS (the broken stops were
# 0.1-11 mm off, at up to twice the RMS).
same_fit() {
  local out
  out=$(/usr/bin/python3 - "$2" "$3" <<'PY'
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
problems = []
for r, f in ((a, sys.argv[1]), (b, sys.argv[2])):
    if r["termination"] != "converged" or r["iterations"] < 1:
        problems.append(f"{f}: {r['termination']} after {r['iterations']} iterations ({r['message'][:120]})")
ea = {p["name"]: p["estimate"] for p in a["parameters"]}
eb = {p["name"]: p["estimate"] for p in b["parameters"]}
worst = max(abs(ea[k] - eb[k]) for k in ea)
if worst > 1e-3:
    problems.append(f"estimates differ by {worst:.3g} mm")
if abs(a["residual_rms"] - b["residual_rms"]) > 1e-6 * a["residual_rms"]:
    problems.append(f"residual RMS {a['residual_rms']:.6g} against {b['residual_rms']:.6g} mm")
print("; ".join(problems))
PY
)
  if [ -z "$out" ]; then ok; else bad "$1: $out"; fi
}
built() { "$kincal" list solvers | grep -q "^$1 "; }

# ---- A6.1 a common scale of the weights changes no backend's result ------------------------
# With reading_std x 1e8 the absolute gradient test (max|J^T r| <= 1e-12) fired after 0-5
# iterations, millimetres from the minimum, on every backend; Ceres' and Ipopt's own gradient
# tests are absolute too.
for solver in lm gn ceres ipopt; do
  if ! built "$solver"; then
    echo "skipped: A6.1 with $solver (not in this build)"
    continue
  fi
  "$kincal" calibrate --model M.json --data D.csv --solver "$solver" --json R1.json >/dev/null 2>&1
  for scaled in Mbig Msmall; do
    rm -f R2.json
    "$kincal" calibrate --model $scaled.json --data D.csv --solver "$solver" --json R2.json \
      >/dev/null 2>e.txt
    check "A6.1: $solver with reading_std x ${scaled#M}" 0 $? e.txt
    same_fit "A6.1: $solver with reading_std x ${scaled#M} against x 1" R1.json R2.json
  done
done
# The noise stated on the command line: --noise-std 1e6mm stopped at twice the optimal RMS.
"$kincal" calibrate --model plain.json --data D.csv --noise-std 0.0072mm --json R1.json \
  >/dev/null 2>&1
"$kincal" calibrate --model plain.json --data D.csv --noise-std 1e6mm --json R2.json >/dev/null 2>e.txt
check "A6.1: calibrate --noise-std 1e6mm" 0 $? e.txt
same_fit "A6.1: --noise-std 1e6mm against 0.0072mm" R1.json R2.json

# ---- A6.1 a robust loss's delta scales the cost too ------------------------------------------
# huber:1e-20 makes the cost ~1e-20 |r|_1: every backend stopped "converged after 0
# iterations" at the nominal's RMS (10.76 mm). The L1-like fit converges slowly (to the limit,
# or to a stop), but far from where it started.
for solver in lm ceres; do
  if ! built "$solver"; then
    echo "skipped: A6.1 huber with $solver (not in this build)"
    continue
  fi
  rm -f R2.json
  "$kincal" calibrate --model M.json --data D.csv --solver "$solver" --loss huber:1e-20 \
    --json R2.json >/dev/null 2>e.txt
  [ -s R2.json ] || bad "A6.1: $solver --loss huber:1e-20 wrote no report: $(head -c 300 e.txt)"
  out=$(/usr/bin/python3 - R2.json <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
if r["iterations"] < 10 or r["residual_rms"] > 0.01:
    print(f"{r['termination']} after {r['iterations']} iterations at RMS {r['residual_rms']:.4g} mm "
          f"({r['message'][:100]})")
PY
)
  if [ -z "$out" ]; then ok; else bad "A6.1: $solver --loss huber:1e-20: $out"; fi
done

# ---- A6.2 --max-iterations 0 is bad input -----------------------------------------------------
# It made calibrate write the nominal model as a calibration and exit 0.
for n in 0 -1; do
  rm -f C0.json
  "$kincal" calibrate --model M.json --data D.csv --max-iterations $n --out C0.json >/dev/null 2>e.txt
  check "A6.2: calibrate --max-iterations $n" 2 $? e.txt "--max-iterations"
  [ -e C0.json ] && bad "A6.2: calibrate --max-iterations $n wrote C0.json" || ok
done
"$kincal" simulate --model M.json --poses 30 --max-iterations 0 --json S0.json --write-data D0.csv \
  >/dev/null 2>e.txt
check "A6.2: simulate --max-iterations 0" 2 $? e.txt "--max-iterations"
[ -e S0.json ] || [ -e D0.csv ] && bad "A6.2: simulate --max-iterations 0 wrote its outputs" || ok
"$kincal" reproduce --trials 1 --max-iterations 0 --out R0 >/dev/null 2>e.txt
check "A6.2: reproduce --max-iterations 0" 2 $? e.txt "--max-iterations"
[ -e R0 ] && bad "A6.2: reproduce --max-iterations 0 created R0" || ok
"$kincal" solver-suite --solver lm --problem mgh01_rosenbrock --max-iterations 0 >/dev/null 2>e.txt
check "A6.2: solver-suite --max-iterations 0" 2 $? e.txt "--max-iterations"
no_temporaries "A6.2"
