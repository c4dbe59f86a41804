# Section "freedoms" of the third audit (issue 35).
#
# A7: gauge freedoms are fixed automatically. An arm calibrated from joint angles alone (a ball
# put into sockets whose positions are unknown, 50 mm known between two of them) cannot see
# where the whole setup stands: moving the base and every socket together changes no fit. A
# turn of the setup still shows in the Jacobian, through the balls' misses at the start, so
# the automatic choice of an imported arm's parameters (no --free/--fix) kept the base's
# three rotations as if the data determined them: 82 parameters on the Panda where 79 are
# identifiable, 44 for 41 on the KUKA iiwa14, with standard deviations of 0.03-0.09 rad and
# the sockets' positions 10-50 mm, which describe nothing. The cases run the example's own
# steps (examples/robot_sockets/run.py) on the public data.
example=$here/../../examples/robot_sockets/run.py
sockets=$datasets/robot-sockets
# freedoms_socket_fit ROBOT: the example's model and training data for ROBOT in ROBOT/, then
# its model with every parameter free (as kincal model --urdf imports an arm) as ROBOT-all.json.
freedoms_socket_fit() {
  py "$example" "$sockets" --robot "$1" --kincal "$kincal" --out "$1" >"$1.txt" 2>&1 ||
    { bad "A7 fixture: run.py --robot $1 failed: $(tail -c 400 "$1.txt")"; return 1; }
  py - "$1/$1-sockets.json" "$1-all.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
m["free"] = ["*"]
json.dump(m, open(sys.argv[2], "w"), indent=1)
PY
}
# freedoms_kept ROBOT KEPT OF: calibrate without --free/--fix keeps KEPT of OF, fixes the base
# frame (the measurement frame; each rotation named as a turn of the whole setup), keeps every
# socket, each with a standard deviation under 1 mm; observability lists the same choice.
freedoms_kept() {
  local robot=$1 kept=$2 of=$3
  "$kincal" calibrate --model "$robot-all.json" --data "$robot/train.csv" --out "$robot-cal.json" \
    --json "$robot-report.json" >"$robot-cal.txt" 2>"$robot-cal.err"
  check "A7: $robot, every parameter free: calibrate" 0 $? "$robot-cal.err" \
    "the data determine $kept of the $of free parameters"
  for axis in x y z; do
    has "$robot-cal.txt" "^  base\.r$axis +the base frame, rotation about $axis .*a turn of the whole setup, which changes no fit \(a gauge freedom\)" \
      "A7: $robot: base.r$axis is fixed as a turn of the whole setup"
  done
  "$kincal" observability --model "$robot-all.json" --data "$robot/train.csv" --json "$robot-obs.json" \
    >"$robot-obs.txt" 2>"$robot-obs.err"
  check "A7: $robot: observability" 0 $? "$robot-obs.err"
  has "$robot-obs.txt" "numerical rank $kept \(" "A7: $robot: observability's numerical rank"
  has "$robot-obs.txt" "3 turn\(s\) of the whole setup change no fit" "A7: $robot: observability names the turns"
  py - "$robot-report.json" "$robot-obs.json" "$kept" >"$robot-check.txt" 2>&1 <<'PY'
import json, math, sys
report, obs, kept = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), int(sys.argv[3])
names = [p["name"] for p in report["parameters"]]
problems = []
if len(names) != kept:
    problems.append("%d parameters estimated, expected %d" % (len(names), kept))
fixed = set(report["fixed_by_identifiability"])
for axis in ("x", "y", "z", "rx", "ry", "rz"):
    if "base." + axis not in fixed:
        problems.append("base.%s is estimated: the base holds the measurement frame" % axis)
for p in report["parameters"]:
    if not (isinstance(p["std"], (int, float)) and math.isfinite(p["std"])):
        problems.append("%s: std %r" % (p["name"], p["std"]))
    elif p["name"].startswith("s_") and not p["std"] < 1.0:
        problems.append("%s: std %.3g mm, a socket's position in the base's coordinates" % (p["name"], p["std"]))
if obs.get("calibrate_keeps") != names:
    problems.append("observability's calibrate_keeps is not calibrate's choice")
if obs.get("measurement_frame_turns") != 3 or obs.get("numerical_rank") != kept:
    problems.append("observability: turns %r, numerical rank %r" % (obs.get("measurement_frame_turns"), obs.get("numerical_rank")))
print("\n".join(problems) if problems else "ok")
PY
  has "$robot-check.txt" "^ok$" "A7: $robot: what calibrate estimates and observability says"
}

if [ ! -d "$sockets/data/panda_2" ] || [ ! -d "$sockets/data/kuka_14" ]; then
  # Not a pass: the cases below need the public socket data, which CI has.
  bad "A7: the socket dataset is not in $sockets (expected data/panda_2/ and data/kuka_14/; set KINCAL_DATASETS to the folder holding robot-sockets/): its cases did not run"
else
  # The Panda, 9 sessions (398 configurations, 18 sockets): 79 = 25 + 3 x 18, where 25 is what
  # a point on a 7R arm determines with a tracker (4 x 7 + 6 - 3) less the 6 of the frame.
  if freedoms_socket_fit panda; then
    freedoms_kept panda 79 115
    # A mask that includes a turn stops, naming it: a turn about joint 1's axis is the base's.
    "$kincal" calibrate --model panda/panda-sockets.json --data panda/train.csv --free 's_*' \
      --free panda_joint2.origin.ry --out turned.json 2>e.txt
    check "A7: an explicit mask with a turn of the setup" 2 $? e.txt \
      "1 of the directions missing being turns of the whole setup.*null directions: panda_joint2\.origin\.ry .*a turn of the whole setup"
    [ -e turned.json ] && bad "A7: turned.json written although calibrate stopped" || ok
    # The example's own mask has no turn: nothing is fixed, nothing said about one.
    "$kincal" calibrate --model panda/panda-sockets.json --data panda/train.csv --free 's_*' \
      --out own.json --json own-report.json >own.txt 2>e.txt
    check "A7: the example's own mask" 0 $? e.txt
    lacks e.txt "turn|gauge|fixing the others" "A7: the example's own mask"
  fi
  # The KUKA iiwa14, 3 sessions (134 configurations, 6 sockets): its ball lies on joint 7's
  # axis, so two fewer: 41 = 23 + 3 x 6.
  if freedoms_socket_fit iiwa14; then
    freedoms_kept iiwa14 41 79
  fi
fi
