# Section "python" of the third audit (issue 35): the Python module (python/, docs/python.md)
# gives the program's guarantees. Each case is a Python program run with the module of this
# build (`py`); it exits 0 when the case holds, else fails an assertion that says why. A crash
# (abort, segfault: exit 134, 139) fails the case too.

# pycase DESCRIPTION: runs the Python program given on standard input.
pycase() {
  py - >py.out 2>py.err
  local code=$?
  if [ "$code" = 0 ]; then ok; else bad "$1: exit $code: $(tail -c 400 py.err) $(tail -c 200 py.out)"; fi
}

# ---- data loss: reproduce(out=DIR) replaces only its own directory, in one step ------------
# The program refuses a directory holding anything but its three tables; so must Python.
mkdir notes
echo "the user's own summary" >notes/summary.csv
echo "keep me" >notes/todo.txt
notes_hash=$(hash notes/summary.csv)
"$kincal" reproduce --trials 1 --validation 5 --out notes >/dev/null 2>e.txt
check "reproduce --out notes (the program's rule)" 2 $? e.txt "holds 'todo.txt'"
pycase "reproduce(out='notes') with the user's files in it" <<'PY'
import kincal, kincal.studies
try:
    kincal.studies.reproduce(trials=1, validation=5, out="notes")
except kincal.KincalError as e:
    assert "holds 'todo.txt'" in str(e), e
else:
    raise AssertionError("reproduce(out='notes') wrote into a directory holding todo.txt")
PY
same notes/summary.csv "$notes_hash" "reproduce(out='notes')"
[ "$(cat notes/todo.txt)" = "keep me" ] && ok || bad "reproduce(out='notes'): todo.txt changed"
pycase "reproduce(out='.') (the current directory)" <<'PY'
import kincal, kincal.studies
try:
    kincal.studies.reproduce(trials=1, validation=5, out=".")
except kincal.KincalError as e:
    assert "current directory" in str(e), e
else:
    raise AssertionError("reproduce(out='.') wrote into the current directory")
PY
[ -e summary.csv ] && bad "reproduce(out='.') wrote summary.csv here" || ok
# A directory of its own tables is replaced whole, in one step: a new directory takes its
# place (a new inode; the old one was written in place), with the program's tables.
"$kincal" reproduce --trials 1 --validation 5 --out cli-out >/dev/null 2>e.txt
check "reproduce --out cli-out" 0 $? e.txt
cp -r cli-out py-out
echo "stale" >py-out/trace.csv
inode=$(stat -c %i py-out)
pycase "reproduce(out='py-out') over its own tables" <<'PY'
import kincal.studies
doc = kincal.studies.reproduce(trials=1, validation=5, out="py-out")
assert doc["out"] == "py-out", doc["out"]
PY
[ "$(stat -c %i py-out)" != "$inode" ] && ok ||
  bad "reproduce(out='py-out'): the directory was written in place, not swapped in one step"
cmp -s cli-out/summary.csv py-out/summary.csv && ok ||
  bad "reproduce(out=): summary.csv differs from the program's"
# trials.csv as the program's but for the solve times (column 5)
[ "$(cut -d, -f1-4,6- cli-out/trials.csv)" = "$(cut -d, -f1-4,6- py-out/trials.csv)" ] && ok ||
  bad "reproduce(out=): trials.csv differs from the program's"
grep -q stale py-out/trace.csv && bad "reproduce(out=): trace.csv not replaced" || ok
[ "$(ls py-out | tr '\n' ' ')" = "summary.csv trace.csv trials.csv " ] && ok ||
  bad "reproduce(out=): py-out holds $(ls py-out | tr '\n' ' ')"
no_temporaries "reproduce(out=)"

# ---- data loss: what other threads print is not the command's text ---------------------------
# The command reads its model from a FIFO that another thread writes: that thread prints
# (on standard output and error) while the command is certainly running, blocked on it.
pycase "another thread's print during a command" <<'PY'
import faulthandler, os, sys, threading
import kincal

faulthandler.dump_traceback_later(120, exit=True)  # a command that opened the FIFO twice
os.mkfifo("model.fifo")
text = kincal.Model.preset("cube-hexapod").to_json()

def other_thread():
    with open("model.fifo", "w") as fifo:  # returns once the command opened it
        print("OTHER-THREAD-STDOUT", flush=True)
        print("OTHER-THREAD-STDERR", file=sys.stderr, flush=True)
        fifo.write(text)

t = threading.Thread(target=other_thread)
t.start()
report = kincal.simulate(model="model.fifo", poses=30, seed=2, validation=5)
t.join()
with open("report-text.txt", "w") as f:
    f.write(report.text + report.messages)
assert "kincal simulate" in report.text, report.text[:200]
assert "OTHER-THREAD" not in report.text, "another thread's print is in report.text"
assert "OTHER-THREAD" not in report.messages, "another thread's print is in report.messages"
PY
has py.out "OTHER-THREAD-STDOUT" "the other thread's print reaches standard output"
has py.err "OTHER-THREAD-STDERR" "the other thread's print reaches standard error"

# ---- crashes ---------------------------------------------------------------------------------
pycase "a LeastSquaresProblem solved again after its callable raised" <<'PY'
import numpy as np
import kincal

calls = {"n": 0}
def residuals(x):
    calls["n"] += 1
    if calls["n"] == 1:
        raise RuntimeError("first call fails")
    return x - np.array([1.0, 2.0])
problem = kincal.LeastSquaresProblem(residuals, lambda x: np.eye(2), 2, 2)
try:
    kincal.solve(problem, np.zeros(2), "lm")
except RuntimeError as e:
    assert "first call fails" in str(e), e
else:
    raise AssertionError("the callable's exception did not propagate")
result = kincal.solve(problem, np.zeros(2), "lm")  # aborted Python before the fix
assert result.termination == "converged", result.termination
assert np.allclose(result.x, [1.0, 2.0]), result.x
# And again raising: the new exception, not the old one.
calls["n"] = 0
try:
    kincal.solve(problem, np.zeros(2), "gn")
except RuntimeError as e:
    assert "first call fails" in str(e), e
PY
pycase "Model.from_json with 100,000 nested arrays" <<'PY'
import kincal
deep = "[" * 100000 + "]" * 100000
for text in ('{"format": ' + deep + "}", deep):  # the first crashed the module (SIGSEGV)
    try:
        kincal.Model.from_json(text)
    except ValueError as e:
        assert "nesting deeper than 64" in str(e), e
        assert len(str(e).splitlines()) == 1, e
    else:
        raise AssertionError("accepted")
try:
    kincal.Model.from_json(" " * (17 << 20) + "{}")
except ValueError as e:
    assert "larger than the limit of 16 MiB" in str(e), e
else:
    raise AssertionError("17 MiB accepted")
PY

# ---- wrong results: a non-finite Jacobian from Python is no "converged" ----------------------
pycase "kincal.solve with a NaN or infinite Jacobian" <<'PY'
import numpy as np
import kincal

results = []
for bad in (np.nan, np.inf):
    problem = kincal.LeastSquaresProblem(
        lambda x: x - np.array([1.0, 2.0]), lambda x: np.full((2, 2), bad), 2, 2)
    for solver in ("lm", "gn", "ceres", "ipopt", "nlopt:LD_LBFGS", "nlopt:LD_MMA"):
        r = kincal.solve(problem, np.zeros(2), solver)
        results.append((solver, bad, r.termination, r.message))
claims = [r for r in results if r[2] == "converged"]
assert not claims, f"converged on a non-finite Jacobian: {claims}"
unnamed = [r for r in results if "jacobian(x)[0, 0] is" not in r[3]]
assert not unnamed, f"the message does not name the Jacobian's entry: {unnamed}"
PY

# ---- the Python API refuses what the program refuses -----------------------------------------
pycase "Model.from_json with a key given twice" <<'PY'
import json
import kincal
text = kincal.Model.preset("cube-hexapod").to_json()
doubled = text.replace('"version": 1,', '"version": 1,\n  "free": [],', 1)
assert doubled != text
try:
    kincal.Model.from_json(doubled, "twice.json")
except ValueError as e:
    assert "'free' appears twice" in str(e), e
else:
    raise AssertionError("a key given twice was accepted")
PY
pycase "unpickling a Model or Measurements from arbitrary text" <<'PY'
import pickle, struct
import numpy as np
import kincal

good = kincal.Model.preset("cube-hexapod")
assert pickle.loads(pickle.dumps(good)).parameter_names == good.parameter_names
state = good.__getstate__()[0].encode()
pickled = pickle.dumps(good, protocol=2)  # the state's text as BINUNICODE, no frames

def crafted_pickle(text):
    """A Model's pickle whose state is `text`."""
    old = b"X" + struct.pack("<I", len(state)) + state
    assert pickled.count(old) == 1
    new = text.encode()
    return pickled.replace(old, b"X" + struct.pack("<I", len(new)) + new)

text = good.to_json()
for crafted, expected in (
    (text.replace('"version": 1,', '"version": 1, "version": 2,', 1), "appears twice"),
    ('{"format": ' + "[" * 100000 + "]" * 100000 + "}", "nesting deeper than 64"),
    ("not json", "malformed JSON"),
):
    try:
        pickle.loads(crafted_pickle(crafted))
    except ValueError as e:
        assert expected in str(e), e
    else:
        raise AssertionError("a Model pickle of arbitrary text was accepted: " + crafted[:40])

data = kincal.Measurements(np.full((1, 6), 336.81), np.full((1, 1), 500.0),
                           good.actuator_names, good.reading_names)
for field, value in (("actuator_names", ["=cmd|' /C calc'!A0"] + good.actuator_names[1:]),
                     ("reading_names", ["gauge\nleg1"]),
                     ("actuators", np.full((1, 6), np.inf))):
    crafted = pickle.dumps(data)
    copy = pickle.loads(crafted)
    copy.__dict__[field] = value  # the state a crafted pickle carries
    try:
        pickle.loads(pickle.dumps(copy))
    except ValueError:
        pass
    else:
        raise AssertionError("a Measurements pickle with " + field + " = " + repr(value) + " was accepted")
PY
pycase "to_json with an infinite value" <<'PY'
import numpy as np
import kincal
m = kincal.Model.preset("cube-hexapod")
values = m.nominal.copy()
values[3] = np.inf
try:
    text = m.to_json(values)
except ValueError as e:
    assert m.parameter_names[3] in str(e) and "finite" in str(e), e
else:
    raise AssertionError("to_json wrote: " + text[text.find("null") - 40:text.find("null") + 10])
try:
    m.with_values(values)
except ValueError as e:
    assert m.parameter_names[3] in str(e), e
else:
    raise AssertionError("with_values accepted inf")
PY
pycase "Measurements.residuals that overflow to -inf" <<'PY'
import json
import numpy as np
import kincal
doc = json.loads(kincal.Model.preset("cube-hexapod").to_json())
doc["reading_std"] = {"gauge": 0.001}
m = kincal.Model.from_json(json.dumps(doc))
q = np.array([[336.81] * 6, [336.81] * 6])
poses, readings, status, reason = m.forward_kinematics(q)
readings[1, 0] = 1.7e308  # a number, which the weighting by 1/0.001 overflows
data = kincal.Measurements(q, readings, m.actuator_names, m.reading_names)
try:
    r, J, names = data.residuals(m)
except ValueError as e:
    assert "row 1, reading 'gauge'" in str(e) and "-inf" in str(e), e
else:
    raise AssertionError("residuals returned " + repr(r))
PY
pycase "Measurements.write with column names kincal would not read back" <<'PY'
import os
import numpy as np
import kincal
m = kincal.Model.preset("cube-hexapod")
good = kincal.Measurements(np.full((1, 6), 336.81), np.full((1, 1), 500.0),
                           m.actuator_names, m.reading_names)
good.write("good.csv")
back = kincal.Measurements.read("good.csv", m)
assert np.array_equal(back.actuators, good.actuators) and np.array_equal(back.readings, good.readings)
for names in (["=cmd|' /C calc'!A0"] + m.actuator_names[1:], ["leg1,leg7"] + m.actuator_names[1:],
              ["leg1\nleg1"] + m.actuator_names[1:], ["leg1"] * 6, ["#leg1"] + m.actuator_names[1:],
              ["x" * 200] + m.actuator_names[1:]):
    data = kincal.Measurements(good.actuators, good.readings, m.actuator_names, m.reading_names)
    data.actuator_names = names  # set after construction, as a user may
    try:
        data.write("bad.csv")
    except ValueError as e:
        assert "column" in str(e), e
    else:
        raise AssertionError("wrote a column named " + repr(names))
    assert not os.path.exists("bad.csv"), names
PY
no_temporaries "Measurements.write"
