#!/usr/bin/env bash
# The second hostile audit's cases (issue 19), kept as a regression script: each case runs the
# real kincal binary the way the audit did and checks the exit code, the one-line message and
# that no file was replaced or left behind. Prints "N passed, N failed"; exit 1 on a failure.
# Usage: hostile_audit_test.sh KINCAL
set -uo pipefail
kincal=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
passed=0
failed=0

ok() { passed=$((passed + 1)); }
bad() {
  failed=$((failed + 1))
  echo "FAILED: $*"
}
# check DESCRIPTION EXPECTED_EXIT ACTUAL_EXIT [STDERR_FILE PATTERN]
check() {
  local what=$1 want=$2 got=$3
  if [ "$got" != "$want" ]; then
    bad "$what: exit $got, expected $want${4:+ (stderr: $(head -c 300 "$4"))}"
    return
  fi
  if [ $# -ge 5 ] && ! grep -q -- "$5" "$4"; then
    bad "$what: stderr lacks '$5': $(head -c 300 "$4")"
    return
  fi
  if [ $# -ge 4 ] && [ "$want" = 2 ] && [ "$(wc -l <"$4")" -ne 1 ]; then
    bad "$what: expected one line on stderr, got: $(head -c 300 "$4")"
    return
  fi
  ok
}
# same FILE HASH DESCRIPTION: the file still has the content it had
same() {
  if [ "$(sha256sum <"$1")" != "$2" ]; then bad "$3: $1 was replaced"; else ok; fi
}
hash() { sha256sum <"$1"; }
no_temporaries() {
  if ls -A | grep -q 'kincal-tmp'; then bad "$1: temporary files left: $(ls -A | grep kincal-tmp)"; else ok; fi
}

# ---- fixtures: the cube hexapod with its gauge's noise, simulated data, a calibration -------
"$kincal" model --out plain.json >/dev/null
python3 - <<'PY'
import json
m = json.load(open("plain.json"))
m["reading_std"] = {"gauge": 0.0125 / 3 ** 0.5}
json.dump(m, open("M.json", "w"), indent=2)
PY
"$kincal" simulate --model M.json --poses 60 --noise-half-width 0.0125 --seed 5 --validation 1 \
  --write-data D.csv >/dev/null 2>&1 || { echo "FAILED: fixture simulate"; exit 1; }
"$kincal" calibrate --model M.json --data D.csv --out C.json --json R.json >/dev/null 2>&1 ||
  { echo "FAILED: fixture calibrate"; exit 1; }
cp D.csv H.csv
# Other data, so that a calibration that should not be written would change C.json.
head -n -10 D.csv >D2.csv
c_hash=$(hash C.json)
r_hash=$(hash R.json)

# ---- 1. standard output is checked ----------------------------------------------------------
"$kincal" export --model C.json --format json >/dev/full 2>e.txt
check "1: export --format json > /dev/full" 2 $? e.txt "cannot write standard output"
"$kincal" model >/dev/full 2>e.txt
check "1: model > /dev/full" 2 $? e.txt "cannot write standard output"
"$kincal" fk --model C.json --data D.csv >/dev/full 2>e.txt
check "1: fk --data > /dev/full" 2 $? e.txt "cannot write standard output"
"$kincal" validate --model C.json --data H.csv --json - >/dev/full 2>e.txt
check "1: validate --json - > /dev/full" 2 $? e.txt "cannot write standard output"
"$kincal" design --model M.json --noise-std 0.0072mm --poses 30 --out T.csv --json - >/dev/full 2>e.txt
check "1: design --json - > /dev/full" 2 $? e.txt "cannot write standard output"
[ -e T.csv ] && bad "1: design wrote T.csv although its --json could not be written" || ok
"$kincal" export --model C.json --format json >&- 2>e.txt
check "1: export with standard output closed" 2 $? e.txt "cannot write standard output"
"$kincal" list >/dev/full 2>e.txt
check "1: list > /dev/full" 2 $? e.txt "cannot write standard output"
"$kincal" --help >/dev/full 2>e.txt
check "1: --help > /dev/full" 2 $? e.txt "cannot write standard output"
"$kincal" calibrate --model M.json --data D2.csv --out C.json --json - >/dev/full 2>e.txt
check "1: calibrate --out C.json --json - > /dev/full" 2 $? e.txt "cannot write standard output"
same C.json "$c_hash" "1: calibrate --json - > /dev/full"
"$kincal" calibrate --model M.json --data D2.csv --out C.json >/dev/full 2>e.txt
check "1: calibrate --out C.json > /dev/full (its summary)" 2 $? e.txt "cannot write standard output"
same C.json "$c_hash" "1: calibrate summary > /dev/full"
no_temporaries "1"

# ---- 2. a failing device output leaves the files as they were ------------------------------
"$kincal" calibrate --model M.json --data D2.csv --out C.json --json /dev/full >/dev/null 2>e.txt
check "2: calibrate --json /dev/full" 2 $? e.txt "cannot write '/dev/full'"
same C.json "$c_hash" "2: calibrate --json /dev/full"
"$kincal" design --model M.json --noise-std 0.0072mm --poses 30 --out T.csv >/dev/null 2>&1
t_hash=$(hash T.csv)
"$kincal" design --model M.json --noise-std 0.0072mm --poses 30 --seed 9 --out T.csv --html /dev/full >/dev/null 2>e.txt
check "2: design --html /dev/full" 2 $? e.txt "cannot write '/dev/full'"
same T.csv "$t_hash" "2: design --html /dev/full"
no_temporaries "2"

# ---- 8, 9, 10. one name policy ---------------------------------------------------------------
name_model() {  # FILE NAME_AS_JSON: the PUMA 560 with its first joint renamed
  "$kincal" model --preset puma560 --out arm.json >/dev/null
  python3 - "$1" "$2" <<'PY'
import json, sys
m = json.load(open("arm.json"))
name = json.loads(sys.argv[2])
m["mechanism"]["joints"][0]["name"] = name
m["free"] = [f.replace("joint1.", name + ".") for f in m["free"]]
open(sys.argv[1], "w").write(json.dumps(m, indent=2))
PY
}
for case in '"a\u0000b"' "\"$(printf 'j%.0s' $(seq 1 200))\"" '"=cmd|\u0027/Ccalc\u0027!A0"' \
  '"@SUM(1+1)"' '"+1"' '"-x"' '"j\u001b[31m"' '"j\u0007"' '"j\nk"'; do
  name_model N.json "$case"
  "$kincal" export --model N.json --format csv --out N.csv >/dev/null 2>e.txt
  check "8-10: joint name $case refused" 2 $? e.txt "mechanism.joints\[0\].name"
  [ -e N.csv ] && { bad "8-10: $case: N.csv written"; rm -f N.csv; } || ok
done
# A name within the policy works end to end and reads back.
name_model N.json '"épaule_1"'
"$kincal" simulate --model N.json --poses 30 --seed 2 --validation 1 --write-data ND.csv \
  >/dev/null 2>e.txt
check "8: a UTF-8 joint name: simulate --write-data" 0 $? e.txt
"$kincal" calibrate --model N.json --data ND.csv >/dev/null 2>e.txt
check "8: kincal reads back the data it wrote with that name" 0 $? e.txt
# A line break or an escape in the model's file name stays inside one comment line.
nl_model=$'new\nline\e[2J.json'
cp M.json "$nl_model"
"$kincal" design --model "$nl_model" --noise-std 0.0072mm --poses 30 --out NT.csv >out.txt 2>e.txt
check "8: design with a line break in the model's file name" 0 $? e.txt
first=$(grep -v '^#' NT.csv | head -n 1)
[ "$first" = "leg1,leg2,leg3,leg4,leg5,leg6,gauge" ] && ok ||
  bad "8: the template's first row is '$first', expected the header"
[ "$(grep -vc '^#' NT.csv)" = 31 ] && ok || bad "8: the template has extra rows"
grep -q $'\e' out.txt NT.csv && bad "10: an escape character reached the terminal or the file" || ok
"$kincal" validate --model C.json --data H.csv --report R.json >out.txt 2>&1
cp C.json "c$(printf '\a')"$'\e'"].json"
"$kincal" validate --model "c$(printf '\a')"$'\e'"].json" --data H.csv >out.txt 2>&1
grep -q $'[\e\a]' out.txt && bad "10: validate printed a control character" || ok

# ---- 11. verify reads a bounded model file ---------------------------------------------------
timeout 20 "$kincal" verify --report R.json --model /dev/zero >/dev/null 2>e.txt
check "11: verify --model /dev/zero" 2 $? e.txt "larger than the limit"

# ---- 13. a file name JSON cannot hold is refused before the work -----------------------------
latin=$'\xe9t\xe9'
"$kincal" design --model M.json --noise-std 0.0072mm --poses 30 --out "$latin.csv" --json d.json >/dev/null 2>e.txt
check "13: design --out with a non-UTF-8 name" 2 $? e.txt "not valid UTF-8"
"$kincal" validate --model C.json --data H.csv --json "$latin.json" >/dev/null 2>e.txt
check "13: validate --json with a non-UTF-8 name" 2 $? e.txt "not valid UTF-8"
cp R.json "$latin.json"
"$kincal" verify --report "$latin.json" --model C.json --json v.json >/dev/null 2>e.txt
check "13: verify --report with a non-UTF-8 name" 2 $? e.txt "not valid UTF-8"
[ -e d.json ] || [ -e v.json ] && bad "13: an output was written" || ok

# ---- 14. a file-size limit is an error, with the default signal handling -------------------
python3 - "$kincal" <<'PY'
import os, resource, signal, subprocess, sys
def limit():
    signal.signal(signal.SIGXFSZ, signal.SIG_DFL)
    resource.setrlimit(resource.RLIMIT_FSIZE, (2048, 2048))
r = subprocess.run([sys.argv[1], "design", "--model", "M.json", "--poses", "60", "--out",
                    "big.csv"], preexec_fn=limit, capture_output=True, text=True)
open("xfsz.txt", "w").write(f"{r.returncode}\n{r.stderr}")
PY
code=$(head -n 1 xfsz.txt)
tail -n +2 xfsz.txt >e.txt
check "14: ulimit -f with SIGXFSZ at its default" 2 "$code" e.txt "File too large"
[ -e big.csv ] && bad "14: big.csv written" || ok
no_temporaries "14"

# ---- 15. read-only and hard-linked outputs are refused ---------------------------------------
cp C.json RO.json
chmod 0444 RO.json
ro_hash=$(hash RO.json)
"$kincal" calibrate --model M.json --data D.csv --out RO.json >/dev/null 2>e.txt
check "15: a read-only output" 2 $? e.txt "is read-only"
same RO.json "$ro_hash" "15: read-only output"
cp C.json HL.json
ln HL.json HL2.json
"$kincal" calibrate --model M.json --data D.csv --out HL.json >/dev/null 2>e.txt
check "15: a hard-linked output" 2 $? e.txt "hard links"
[ HL.json -ef HL2.json ] && ok || bad "15: the hard link was cut"

# ---- 17. kincal reads the files it writes, and real instruments' logs -----------------------
python3 - <<'PY'
# 600,000 rows (about 70 MB, beyond the old 64 MiB limit) of the hexapod's home leg lengths.
import json, subprocess
row = "336.8100000000001,336.8100000000001,336.8100000000001,336.8100000000001,336.8100000000001,336.8100000000001,500.00000000000011\n"
with open("big.csv", "w") as f:
    f.write("leg1,leg2,leg3,leg4,leg5,leg6,gauge\n")
    f.write(row * 600000)
PY
"$kincal" fk --model M.json --data big.csv --out /dev/null >/dev/null 2>e.txt
code=$?
if [ "$(stat -c %s big.csv)" -le $((64 << 20)) ]; then bad "17: big.csv is not beyond 64 MiB"; fi
grep -q "larger than the limit" e.txt && bad "17: a 70 MB file is refused: $(head -c 200 e.txt)" || ok
[ "$code" -le 1 ] && ok || bad "17: fk on a 70 MB file: exit $code: $(head -c 200 e.txt)"
"$kincal" fk --model M.json --data big.csv --out /dev/null --max-data-size 1MB >/dev/null 2>e.txt
check "17: --max-data-size 1MB" 2 $? e.txt "raise the limit with --max-data-size"
"$kincal" fk --model M.json --data big.csv --out /dev/null --max-data-size 1parsec >/dev/null 2>e.txt
check "17: --max-data-size with a bad unit" 2 $? e.txt "expected a size"
rm -f big.csv

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
