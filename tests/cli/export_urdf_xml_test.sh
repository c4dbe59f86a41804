#!/usr/bin/env bash
# The URDF kincal export writes is XML that a standard parser reads: every preset arm, with
# its joints chained from world (the tracker's frame) through base_link and tool0 to tcp (the
# measured point), even from a model file whose name holds XML's
# special characters. Skipped (77) only without python3.
set -euo pipefail
kincal=$1
command -v python3 >/dev/null 2>&1 || { echo "skipped: python3 is not installed"; exit 77; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for preset in puma560 ur5; do
  # A file name that an XML comment or attribute could choke on: "--", "&", "<".
  model="$dir/${preset}--a&b<c.json"
  "$kincal" model --preset "$preset" --out "$model"
  "$kincal" export --model "$model" --format urdf --out "$dir/$preset.urdf"
  python3 - "$dir/$preset.urdf" "$model" <<'PY'
import sys, xml.etree.ElementTree as ET
robot = ET.parse(sys.argv[1]).getroot()
# The header comment (before the root) names the model file as written: a comment expands no
# entities, so only its "--" is split.
name = sys.argv[2].rsplit("/", 1)[-1].replace("--", "- -")
with open(sys.argv[1]) as f:
    head = f.read().split("<robot", 1)[0]
assert name in head, (name, head)
assert robot.tag == "robot", robot.tag
links = {l.get("name") for l in robot.findall("link")}
parent = "world"
for joint in robot.findall("joint"):
    assert joint.find("parent").get("link") == parent, (joint.get("name"), parent)
    child = joint.find("child").get("link")
    assert child in links, child
    if joint.get("type") != "fixed":
        lim = joint.find("limit")
        assert float(lim.get("lower")) < float(lim.get("upper")), joint.get("name")
    parent = child
assert parent == "tcp", parent
print(sys.argv[1].rsplit("/", 1)[-1], "parses:", len(robot.findall("joint")), "joints")
PY
done
