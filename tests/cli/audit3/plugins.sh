# Section "plugins" of the third audit (issue 35): which tokens load a plug-in, what a
# plug-in may register and throw, two calibrations writing the same outputs at once, and
# messages that blamed the wrong thing.
# The test plug-ins (tests/plugins/) come from the ctest's environment; run by hand, from the
# build tree beside $kincal.
plugin_dir=$(cd "$(dirname "$kincal")/../tests/plugins" 2>/dev/null && pwd)
mis=${KINCAL_TEST_MISBEHAVING_PLUGIN:-$plugin_dir/libtest_plugin_misbehaving.so}
[ -f "$mis" ] || {
  bad "the misbehaving test plug-in is missing: '$mis' (build the target test_plugin_misbehaving)"
  return
}
source_dir=$here/../..

# ---- fixtures: puma560, two data sets from it --------------------------------------------
"$kincal" model --preset puma560 --out M.json >/dev/null
for seed in 1 2; do
  "$kincal" simulate --model M.json --poses 30 --noise-half-width 0.01 --seed $seed \
    --validation 1 --write-data D$seed.csv >/dev/null 2>&1 || bad "fixture: simulate seed $seed"
done

# ---- 1. only a real --plugin option loads a plug-in (the value of --data / --out never) ------
# The misbehaving plug-in creates $marker when its registration runs: its code ran. A copy
# beside the outputs, named relatively, so that --out --plugin=evil.so names a file here.
marker=$PWD/plugin-ran
loaded() { [ -e "$marker" ]; }
cp "$mis" evil.so
evil_hash=$(hash evil.so)
rm -f "$marker"
KINCAL_TEST_PLUGIN_MARKER=$marker "$kincal" calibrate --model M.json --data --plugin=evil.so \
  --out C.json >/dev/null 2>e.txt
check "1: calibrate --data --plugin=evil.so (--data's value)" 2 $? e.txt \
  "--plugin=evil.so: cannot open measurement file"
loaded && bad "1: calibrate --data --plugin=evil.so loaded the plug-in (its code ran)" || ok
[ -e C.json ] && bad "1: calibrate --data --plugin=evil.so wrote C.json" || ok
rm -f "$marker"
KINCAL_TEST_PLUGIN_MARKER=$marker "$kincal" calibrate --model M.json --data D1.csv \
  --out --plugin=evil.so >/dev/null 2>e.txt
check "1: calibrate --out --plugin=evil.so (--out's value)" 0 $? e.txt
loaded && bad "1: calibrate --out --plugin=evil.so loaded the plug-in" || ok
has ./--plugin=evil.so '"format": "kincal-model"' "1: --out --plugin=evil.so writes the model there"
same evil.so "$evil_hash" "1: calibrate --out --plugin=evil.so"
rm -f "$marker" ./--plugin=evil.so
KINCAL_TEST_PLUGIN_MARKER=$marker "$kincal" export --model M.json --format --plugin evil.so \
  >/dev/null 2>e.txt
check "1: export --format --plugin evil.so (--format's value, then a stray word)" 2 $? e.txt \
  "positional"
loaded && bad "1: export --format --plugin evil.so loaded the plug-in" || ok
rm -f "$marker"
KINCAL_TEST_PLUGIN_MARKER=$marker "$kincal" list -- --plugin=evil.so >/dev/null 2>e.txt
check "1: list -- --plugin=evil.so (an operand)" 2 $? e.txt "cannot list '--plugin=evil.so'"
loaded && bad "1: list -- --plugin=evil.so loaded the plug-in" || ok
# A real option token still loads it, with either spelling, anywhere among the options.
rm -f "$marker"
KINCAL_TEST_PLUGIN_MARKER=$marker "$kincal" list models --plugin="$mis" >o.txt 2>e.txt
check "1: list models --plugin=FILE" 0 $? e.txt
has o.txt "misbehaving-null" "1: list models --plugin=FILE lists the plug-in's presets"
loaded || bad "1: list models --plugin=FILE did not load the plug-in"
KINCAL_TEST_PLUGIN_MARKER=$marker "$kincal" simulate --plugin "$mis" --preset puma560 \
  --noise-half-width 0 --validation 1 --solver misbehaving-throwing-solver >/dev/null 2>e.txt
check "1: simulate --plugin FILE before the other options" 2 $? e.txt \
  "solver 'misbehaving-throwing-solver'"

# ---- 2. what a plug-in registers or builds follows the name policy -------------------------
KINCAL_TEST_PLUGIN_MODE=escape-description "$kincal" list --plugin "$mis" >o.txt 2>e.txt
check "2: a preset description with an escape sequence" 2 $? e.txt \
  "description of preset 'misbehaving-escape' contains the control character U\+001B"
lacks o.txt $'\x1b' "2: kincal list printed the escape sequence"
lacks e.txt $'\x1b' "2: the message printed the escape sequence"
KINCAL_TEST_PLUGIN_MODE=formula-preset "$kincal" list --plugin "$mis" >o.txt 2>e.txt
check "2: a preset named like a formula" 2 $? e.txt "preset '=cmd.*starts with '='"
KINCAL_TEST_PLUGIN_MODE=formula-solver "$kincal" list --plugin "$mis" >o.txt 2>e.txt
check "2: a solver named like a formula" 2 $? e.txt "solver '=cmd.*starts with '='"
"$kincal" simulate --plugin "$mis" --preset misbehaving-formula-columns --validation 1 \
  --write-data F.csv >/dev/null 2>e.txt
check "2: simulate --write-data of a preset whose columns are formulas" 2 $? e.txt \
  "preset 'misbehaving-formula-columns' makes a model whose sensor '=cmd"
[ -e F.csv ] && bad "2: a CSV with a formula header was written: $(sed -n 3p F.csv)" || ok
"$kincal" model --plugin "$mis" --preset misbehaving-formula-columns --out F.json \
  >/dev/null 2>e.txt
check "2: model --preset of a preset whose names are formulas" 2 $? e.txt \
  "preset 'misbehaving-formula-columns' makes a model whose sensor '=cmd"
[ -e F.json ] && bad "2: a model file with formula names was written" || ok

# ---- 3. a plug-in throwing a non-std::exception or returning null: one line, exit 2 --------
KINCAL_TEST_PLUGIN_MODE=throw-int "$kincal" list --plugin "$mis" >/dev/null 2>e.txt
check "3: registration throws 42" 2 $? e.txt \
  "plug-in '.*misbehaving.*': its registration threw an exception that is not a std::exception"
"$kincal" simulate --plugin "$mis" --preset misbehaving-throws --validation 1 >/dev/null 2>e.txt
check "3: a preset's factory throws 42" 2 $? e.txt \
  "plug-in '.*misbehaving.*': preset 'misbehaving-throws' threw an exception that is not"
"$kincal" simulate --plugin "$mis" --preset misbehaving-null --validation 1 >/dev/null 2>e.txt
check "3: a preset's factory returns null" 2 $? e.txt \
  "plug-in '.*misbehaving.*': preset 'misbehaving-null' returned null"
"$kincal" simulate --plugin "$mis" --preset puma560 --noise-half-width 0 --validation 1 \
  --solver misbehaving-null-solver >/dev/null 2>e.txt
check "3: a solver factory returns null" 2 $? e.txt \
  "plug-in '.*misbehaving.*': solver 'misbehaving-null-solver''s factory returned null"
"$kincal" calibrate --plugin "$mis" --model M.json --data D1.csv --out C.json \
  --solver misbehaving-null-solver >/dev/null 2>e.txt
check "3: calibrate with a solver factory that returns null" 2 $? e.txt \
  "solver 'misbehaving-null-solver''s factory returned null"
[ -e C.json ] && bad "3: calibrate wrote C.json with a null solver" || ok
"$kincal" simulate --plugin "$mis" --preset misbehaving-throwing-sensor --validation 1 \
  >/dev/null 2>e.txt
check "3: a sensor's predict() throws 42" 2 $? e.txt \
  "a plug-in threw an exception that is not a std::exception \(loaded: '.*misbehaving"

# ---- 4. two calibrations on the same --out/--json leave a consistent pair --------------------
# The first run sleeps between its two renames (a test hook, framework/io/output_files.hpp);
# the second starts meanwhile with other data. Without the lock, the second's report and model
# land in the first one's window: the first's model is renamed last, beside the second's report.
listing() { ls -A | grep -v -x -e C.json -e R.json -e 'o.txt' -e 'e[12]*.txt' | sort; }
before=$(listing)
for round in 1 2 3 4 5; do
  KINCAL_TEST_PAUSE_BETWEEN_RENAMES_MS=700 "$kincal" calibrate --model M.json --data D1.csv \
    --out C.json --json R.json >/dev/null 2>e1.txt &
  first=$!
  sleep 0.2
  "$kincal" calibrate --model M.json --data D2.csv --out C.json --json R.json >/dev/null 2>e2.txt &
  second=$!
  wait $first
  check "4: round $round, the first calibrate" 0 $? e1.txt
  wait $second
  check "4: round $round, the second calibrate" 0 $? e2.txt
  "$kincal" verify --report R.json --model C.json >o.txt 2>e.txt
  check "4: round $round, verify after two concurrent calibrations" 0 $? e.txt
done
# Three at once without the hook, many times: every set consistent.
for round in $(seq 1 20); do
  for data in D1.csv D2.csv D1.csv; do
    "$kincal" calibrate --model M.json --data $data --out C.json --json R.json >/dev/null 2>&1 &
  done
  wait
  "$kincal" verify --report R.json --model C.json >o.txt 2>e.txt ||
    bad "4: unpaused round $round: verify failed: $(head -c 300 e.txt)"
done
no_temporaries "4: concurrent calibrations"
after=$(listing)
[ "$before" = "$after" ] && ok ||
  bad "4: files left beside the outputs: $(comm -13 <(echo "$before") <(echo "$after"))"

# ---- 5. messages that blamed the wrong thing ----------------------------------------------
# A plug-in's NaN derivative: not "no reading depends on ...", but where the NaN is.
"$kincal" simulate --plugin "$mis" --preset misbehaving-nan-jacobian --validation 1 \
  >/dev/null 2>e.txt
check "5: simulate with a NaN Jacobian" 2 $? e.txt \
  "whitened Jacobian .* is nan at configuration [0-9]+, reading 'tracker.x' of sensor 'tracker'"
lacks e.txt "no reading depends" "5: simulate with a NaN Jacobian blames the data"
"$kincal" model --plugin "$mis" --preset misbehaving-nan-jacobian --out N.json >/dev/null 2>&1 ||
  bad "5: fixture model --preset misbehaving-nan-jacobian"
"$kincal" calibrate --plugin "$mis" --model N.json --data D1.csv --out C5.json >/dev/null 2>e.txt
check "5: calibrate with a NaN Jacobian" 2 $? e.txt \
  "D1.csv: the whitened Jacobian .* is nan at configuration 1, reading 'tracker.x' of sensor 'tracker' .*misbehaving-tracker"
[ -e C5.json ] && bad "5: calibrate with a NaN Jacobian wrote C5.json" || ok

# A constraint std of 1e-300: the whitened rows overflow; the message names the constraint.
"$kincal" model --preset ur5-urdf-socket --out S.json >/dev/null
/usr/bin/python3 - <<'PY'
import json
m = json.load(open("S.json"))
m["sensors"] = [{"type": "socket", "name": "socket0", "point": [-400, -100, 300]},
                {"type": "socket", "name": "socket1", "point": [-400, -51, 310]}]
m["free"] = ["socket*", "tool.x", "tool.y", "tool.z"]
for std, name in ((0.05, "S_good.json"), (1e-300, "S_tiny.json")):
    m["constraints"] = [{"type": "fixture-distance", "between": ["socket0", "socket1"],
                         "distance": 50, "std": std}]
    json.dump(m, open(name, "w"), indent=1)
PY
"$kincal" simulate --model S_good.json --poses 40 --noise-half-width 0.01 --validation 1 \
  --write-data SD.csv >/dev/null 2>&1 || bad "5: fixture simulate of two sockets"
"$kincal" calibrate --model S_tiny.json --data SD.csv --out C5.json >/dev/null 2>e.txt
check "5: calibrate with a constraint std of 1e-300" 2 $? e.txt \
  "constraint fixture-distance .*socket0 - socket1.* \(std 1e-300 mm\).*beyond 1e100"
lacks e.txt "no reading depends" "5: a constraint std of 1e-300 blames the data"
[ -e C5.json ] && bad "5: calibrate with a constraint std of 1e-300 wrote C5.json" || ok

# A subnormal or zero prior std is bad input, named as such.
"$kincal" calibrate --model M.json --data D1.csv --noise-std 0.01mm --prior-std 'joint*=1e-320' \
  --out C5.json >/dev/null 2>e.txt
check "5: --prior-std 'joint*=1e-320'" 2 $? e.txt \
  "^kincal calibrate: error: --prior-std 'joint\*=1e-320': '1e-320' is not a std between 1e-150 and 1e150"
lacks e.txt "determine only" "5: --prior-std 1e-320 blames the data"
[ -e C5.json ] && bad "5: calibrate --prior-std 1e-320 wrote C5.json" || ok
"$kincal" design --model M.json --noise-std 0.01mm --poses 30 --prior-std 0mm --out T.csv \
  >/dev/null 2>e.txt
check "5: design --prior-std 0mm" 2 $? e.txt "--prior-std '0mm'"
[ -e T.csv ] && bad "5: design --prior-std 0mm wrote T.csv" || ok
/usr/bin/python3 - <<'PY'
import json
m = json.load(open("M.json"))
m["prior_std"] = {"joint1.a": 1e-320}
json.dump(m, open("M_tiny_prior.json", "w"), indent=1)
PY
"$kincal" calibrate --model M_tiny_prior.json --data D1.csv --noise-std 0.01mm \
  --out C5.json >/dev/null 2>e.txt
check "5: a model file's prior_std of 1e-320" 2 $? e.txt \
  "M_tiny_prior.json: prior_std.*between 1e-150 and 1e150"

# An option's name in a message has two dashes, not four.
"$kincal" model --urdf "$source_dir/examples/ur5-laser-tracker/ur5.urdf" --tip tool0 \
  --point nan,0,0 --out U.json >/dev/null 2>e.txt
check "5: model --urdf --point nan,0,0" 2 $? e.txt "error: --point 'nan,0,0': field 1"
lacks e.txt "----point" "5: model --point names the option ----point"
[ -e U.json ] && bad "5: model --point nan wrote U.json" || ok
