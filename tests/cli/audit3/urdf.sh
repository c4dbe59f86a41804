# Section "urdf" of the third audit (issue 35): `kincal model --urdf` and `kincal export
# --format urdf`. Every model file an import writes here is read back by kincal (urdf_imports);
# every refusal is exit 2, one line, no model file and no temporary file (urdf_refused).

# A three-joint arm: base_link -j1-> l1 -j2-> l2 -j3-> tool; `extra` goes before </robot>.
urdf_arm() {  # FILE [EXTRA_XML] [J2_NAME] [LIMIT_OF_J1]
  local limit='<limit lower="-3" upper="3" effort="1" velocity="1"/>'
  [ -n "${4:-}" ] && limit=$4
  cat >"$1" <<EOF
<robot name="arm">
  <link name="base_link"/>
  <joint name="j1" type="revolute">
    <parent link="base_link"/><child link="l1"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>
    $limit
  </joint>
  <link name="l1"/>
  <joint name="${3:-j2}" type="revolute">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0 0.05 0.2" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <link name="l2"/>
  <joint name="j3" type="revolute">
    <parent link="l2"/><child link="tool"/>
    <origin xyz="0.3 0 0" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <link name="tool"/>
${2:-}
</robot>
EOF
}

# urdf_imports DESCRIPTION URDF [OPTIONS...]: imported (exit 0), and the model file read back.
urdf_imports() {
  local what=$1 file=$2
  shift 2
  rm -f m.json
  "$kincal" model --urdf "$file" --tip tool --out m.json "$@" 2>e.txt
  check "$what: imported" 0 $? e.txt
  if [ -f m.json ]; then
    "$kincal" export --model m.json --format json >/dev/null 2>e.txt
    check "$what: the model file written reads back" 0 $? e.txt
  fi
}

# urdf_refused DESCRIPTION PATTERN URDF [OPTIONS...]: exit 2, one line matching PATTERN, the
# model file it would have replaced as it was, no temporary file. The import runs with 2 GB of address space and 60 s at most
# (the code before issue 35 looped on cycles and read /dev/zero until memory ran out).
urdf_refused() {
  local what=$1 pattern=$2 file=$3
  shift 3
  echo "an older model file" >m.json
  local before
  before=$(hash m.json)
  (
    # AddressSanitizer reserves terabytes of address space for its shadow memory, so under it
    # the 2 GB are its own resident-memory limit instead of ulimit -v.
    if grep -aq __asan_init "$kincal"; then
      export ASAN_OPTIONS="${ASAN_OPTIONS:-}${ASAN_OPTIONS:+:}hard_rss_limit_mb=2000"
    else
      ulimit -v 2000000
    fi
    timeout 60 "$kincal" model --urdf "$file" --tip tool --out m.json "$@"
  ) 2>e.txt
  check "$what" 2 $? e.txt "$pattern"
  same m.json "$before" "$what"
  no_temporaries "$what"
  rm -f m.json
}

# ---- wrong results: a link with two parent joints ------------------------------------------
urdf_arm two_parents.urdf '  <joint name="j2b" type="revolute">
    <parent link="base_link"/><child link="l2"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>'
urdf_refused "a link with two parent joints" \
  "link name=\"l2\".* is the child of two joints, .*joint name=\"j2\".* and .*joint name=\"j2b\"" \
  two_parents.urdf

# ---- crashes: cycles, nesting, size ---------------------------------------------------------
# A cycle of joints away from the root, around the tip (a <-> tool) and around the base.
cat >cycle.urdf <<'EOF'
<robot name="cycle">
  <link name="root"/><link name="a"/><link name="tool"/>
  <joint name="ja" type="revolute"><parent link="tool"/><child link="a"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="jt" type="revolute"><parent link="a"/><child link="tool"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
EOF
urdf_refused "a cycle around the tip" "is its own ancestor.*closes a cycle" cycle.urdf --base root
urdf_refused "a cycle around the base" "is its own ancestor.*closes a cycle" cycle.urdf --base a
sed 's|<parent link="tool"/><child link="a"/>|<parent link="a"/><child link="a"/>|' cycle.urdf >self.urdf
urdf_refused "a joint from a link to itself" "is its own ancestor" self.urdf --base root

# 100,000 elements inside one another (700 KB): the XML parser's recursion crashed.
urdf_arm arm.urdf
py - <<'EOF'
arm = open("arm.urdf").read()
def nested(n):
    return arm.replace("</robot>", "<gazebo>" + "<a>" * n + "</a>" * n + "</gazebo></robot>")
open("deep.urdf", "w").write(nested(100000))
# 64 levels are accepted (robot, gazebo and 62 <a>), 65 are not.
open("depth64.urdf", "w").write(nested(62))
open("depth65.urdf", "w").write(nested(63))
EOF
urdf_refused "100,000 nested elements" "line [0-9]+: elements nested more than 64 deep" deep.urdf
urdf_refused "65 nested elements" "nested more than 64 deep" depth65.urdf
urdf_imports "64 nested elements" depth64.urdf

# Size: read with a model file's limit, checked while reading.
urdf_refused "--urdf /dev/zero" "/dev/zero: larger than the limit of 16 MiB .* for a URDF" /dev/zero
py - <<'EOF'
arm = open("arm.urdf").read()
# 20 MB in a comment: more than a model file may hold.
open("big.urdf", "w").write(arm.replace("</robot>", "<!--" + "x" * 20_000_000 + "--></robot>"))
# 9 MB of quotes: a 9 MB URDF, an 18 MB model file once they are escaped as JSON.
open("quotes.urdf", "w").write(arm.replace("</robot>", "<!--" + '"' * 9_000_000 + "--></robot>"))
# 2 MB: imported, and its model file reads back.
open("fine.urdf", "w").write(arm.replace("</robot>", "<!--" + '"' * 2_000_000 + "--></robot>"))
# 100,001 empty elements (400 KB): more nodes than the limit.
open("nodes.urdf", "w").write(arm.replace("</robot>", "<gazebo>" + "<a/>" * 100_001 + "</gazebo></robot>"))
EOF
urdf_refused "a 20 MB URDF" "big.urdf: larger than the limit of 16 MiB .* for a URDF" big.urdf
urdf_refused "a URDF whose model file would pass 16 MiB" "model file would be [0-9]+ bytes.*16 MiB" quotes.urdf
urdf_imports "a 2 MB URDF" fine.urdf
urdf_refused "100,001 elements" "more than 100000 XML nodes" nodes.urdf

# ---- unclear errors: not UTF-8, limits ------------------------------------------------------
urdf_arm latin1.urdf "" "$(printf 'j\xe9')"
urdf_refused "a Latin-1 joint name" \
  "latin1.urdf: line 9: the value of attribute 'name' in <joint> is not valid UTF-8 \(byte .xE9\)" \
  latin1.urdf
lacks e.txt "type_error|json" "a Latin-1 joint name: a raw JSON library message"
# The same name written as a character reference, with no XML declaration: UTF-8 (TinyXML
# alone gives the byte 0xE9 there).
urdf_arm reference.urdf "" "j&#xE9;"
{ echo '<?xml version="1.0" encoding="ISO-8859-1"?>'; cat reference.urdf; } >reference_latin1.urdf
for file in reference.urdf reference_latin1.urdf; do
  urdf_imports "a character reference in a joint name ($file)" $file
  py - <<'EOF' || bad "a character reference in a joint name ($file): the actuator is not 'jé'"
import json, sys
names = [a["name"] for a in json.load(open("m.json"))["mechanism"]["joints"]]
sys.exit(0 if names == ["j1", "j\u00e9", "j3"] else print(names) or 1)
EOF
done

urdf_arm swapped.urdf "" "" '<limit lower="2" upper="-2" effort="1" velocity="1"/>'
urdf_refused "limits with lower above upper" \
  'line 3: <joint name="j1">: <limit lower="2" upper="-2">: lower is above upper' swapped.urdf
urdf_arm huge.urdf "" "" '<limit lower="-1e308" upper="1e308" effort="1" velocity="1"/>'
urdf_refused "limits of 1e308 rad" \
  '<joint name="j1">: <limit lower="-1e\+308" upper="1e\+308"> is beyond the largest number of degrees' \
  huge.urdf
urdf_arm far.urdf "" "" '<limit lower="1e300" upper="1e301" effort="1" velocity="1"/>'
urdf_imports "limits of 1e300 rad (a model kincal reads)" far.urdf
sed 's|type="revolute">|type="prismatic">|' huge.urdf | sed 's|1e308|1e306|g' >huge_prismatic.urdf
urdf_refused "prismatic limits of 1e306 m" \
  '<joint name="j1">: <limit lower="-1e\+306" upper="1e\+306"> is beyond the largest number of mm' \
  huge_prismatic.urdf

# ---- security: the names policy at import --------------------------------------------------
esc=$(printf '\033')
long=$(printf 'j%.0s' $(seq 129))
for name in "j${esc}[31m" "=j2" "@j2" "j'2" "j;2" "$long" "tool" "j.2" "&#x1B;j2" "+j&amp;2"; do
  urdf_arm named.urdf "" "$name"
  urdf_refused "joint name '$name'" \
    "named.urdf: line 9: <joint name=\".*\">: the name .*; kincal names a measurement column" \
    named.urdf
done
# The base and tip links are names in the model file too.
urdf_arm tipname.urdf
sed -i 's|"tool"|"=tool"|' tipname.urdf
rm -f m.json
"$kincal" model --urdf tipname.urdf --tip =tool --out m.json 2>e.txt
check "tip link '=tool'" 2 $? e.txt "<link name=\"=tool\">: the name starts with '='"
[ -e m.json ] && bad "tip link '=tool': a model file was written" || ok
# A model file with such a link name (edited by hand) is refused by the reader too.
urdf_imports "the arm" arm.urdf
py - <<'EOF'
import json
m = json.load(open("m.json"))
m["mechanism"]["tip_link"] = "tool\u001b[31m"
json.dump(m, open("bad_link.json", "w"))
EOF
"$kincal" export --model bad_link.json --format json >/dev/null 2>e.txt
check "a model file whose tip link breaks the names policy" 2 $? e.txt "tip_link.*control character"

# ---- data loss: the export keeps the user's text byte for byte -----------------------------
# A URDF with white space that matters in texts, character references, processing
# instructions, a DOCTYPE, comments and a CDATA section (both holding an <origin> that is not
# one), a tab, a CRLF line, single quotes, a chain joint without <origin>, one whose <origin>
# has no rpy, and non-chain joints and links.
py - <<'EOF'
text = """<?xml version="1.0" encoding="UTF-8"?>
<?xml-stylesheet type="text/xsl" href="robot.xsl"?>
<!DOCTYPE robot>
<!-- caf\u00e9: a comment holding <origin xyz="9 9 9" rpy="9 9 9"/> & co -->
<robot name="caf&#xE9;bot"   xmlns:xacro="http://www.ros.org/wiki/xacro">
\t<?kincal-test a processing instruction?>
  <link name="base_link">
    <visual><geometry><mesh filename="package://r/m&amp;s.stl"/></geometry></visual>
  </link>\r
  <joint name="j1" type="revolute">
    <parent link="base_link"/>   <child link="l1"/>
    <origin   xyz='0 0 0.1'  rpy="0 0 0" />
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <link name="l1"><inertial><mass value="2.5"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/>
    <!-- j2's origin -->
    <origin xyz="0 0.05 0.2"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <link name="l2"/>
  <joint name="j3" type="revolute">
    <parent link="l2"/><child link="tool"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <link name="tool"/>
  <joint name="side" type="fixed">
    <parent link="l1"/><child link="camera"/>
    <origin xyz="0.01 0.02 0.03" rpy="0.1 0.2 0.3"/>
  </joint>
  <link name="camera"/>
  <gazebo reference="l1">
    <plugin name="p" filename="x.so">  two   spaces
        and a line break: &#xE9; &#233; &lt;tag&gt; &#x1F600; &quot;q&apos; </plugin>
    <data><![CDATA[ a < b && <origin xyz="9 9 9"/> ]]></data>
  </gazebo>
</robot>
<!-- after the robot -->
"""
open("rich.urdf", "w", newline="").write(text)
EOF
urdf_imports "the URDF with everything" rich.urdf
py - <<'EOF'
import json
m = json.load(open("m.json"))
# Corrections on every joint, and a tracker frame: every chain origin changes.
for k, j in enumerate(m["mechanism"]["joints"]):
    j["origin_error"] = {"position": [0.1 * (k + 1), -0.2, 0.3], "rotation_zyx_deg": [0.01, 0.02 * k, -0.03]}
    j["offset_deg"] = 0.5 * (k + 1)
json.dump(m, open("corrected.json", "w"), indent=2)
EOF
"$kincal" export --model corrected.json --format urdf --out rich_out.urdf 2>e.txt
check "export of the URDF with everything" 0 $? e.txt
py - rich.urdf rich_out.urdf <<'EOF' || bad "export of the URDF with everything: not the user's text outside the origins (above)"
import re, sys
import xml.etree.ElementTree as ET

original = open(sys.argv[1], "rb").read().decode("utf-8")
exported = open(sys.argv[2], "rb").read().decode("utf-8")  # also: the export is UTF-8
problems = []

# 1. The text: the header after the declaration, the added block before </robot>, the
# <origin> added to j3: removed, the export must be the original except for the values of
# the chain joints' origins.
declaration = '<?xml version="1.0" encoding="UTF-8"?>'
header = re.match(re.escape(declaration) + r"\n<!-- kincal export:[^\n]*?-->", exported)
if not header:
    problems.append("no header comment right after the declaration")
else:
    exported = declaration + exported[header.end():]
block = re.search(r"  <!-- kincal: the measurement frame.*?</joint>\n.*?</joint>\n(?=</robot>)", exported, re.S)
if not block:
    problems.append("no block of added links and joints before </robot>")
else:
    exported = exported[:block.start()] + exported[block.end():]
added = re.search(r'(<joint name="j3" type="revolute">)(\s*)<origin xyz="[^"]*" rpy="[^"]*"/>', exported)
if not added:
    problems.append("no <origin> added to j3")
else:
    exported = exported[:added.end(1)] + exported[added.end(2) + len(added.group(0)) - len(added.group(1)) - len(added.group(2)):]
origin = re.compile(r"<origin\b[^>]*>")
a, b = origin.split(original), origin.split(exported)
ta, tb = origin.findall(original), origin.findall(exported)
if a != b:
    problems.append("text outside the <origin> tags differs")
    for x, y in zip(a, b):
        if x != y:
            problems.append("first difference: %r -> %r" % (x[:200], y[:200]))
            break
elif len(ta) != len(tb):
    problems.append("%d <origin> tags, %d exported" % (len(ta), len(tb)))
else:
    changed = [(a[i], ta[i], tb[i]) for i in range(len(ta)) if ta[i] != tb[i]]
    joints = [re.search(r'<joint name="(\w+)"[^>]*>\s*(?:<!--[^>]*-->\s*)?(?:<parent[^>]*/>\s*<child[^>]*/>\s*)?(?:<!--[^>]*-->\s*)?$', before) for before, _, _ in changed]
    names = [j.group(1) if j else None for j in joints]
    if names != ["j1", "j2"]:
        problems.append("changed origins after joints %r" % names)
    for before, x, y in changed:
        # Only the values of xyz and rpy change (rpy added where missing).
        strip = lambda t: re.sub(r'(xyz|rpy)=(["\'])[^"\']*\2', r"\1=\2\2", t)
        if strip(x).replace(' rpy=""', "") != strip(y).replace(' rpy=""', "").replace(" rpy=\"\"", ""):
            problems.append("origin tag changed beyond its values: %r -> %r" % (x, y))
        # Numbers with the fewest digits that read back (Python's repr is the shortest).
        for number in " ".join(re.findall(r'(?:xyz|rpy)=["\']([^"\']*)', y)).split():
            if repr(float(number)).removesuffix(".0") != number:
                problems.append("%r is not the shortest form of its number" % number)
    if problems:
        problems.append("changed origins: %r" % [(x, y) for _, x, y in changed])

# 2. The trees, parsed by Python's XML parser with comments and processing instructions: the
# same except the chain origins' values and the added nodes (and the white space that comes
# before them, compared byte for byte above).
def tree(path):
    parser = ET.XMLParser(target=ET.TreeBuilder(insert_comments=True, insert_pis=True))
    return ET.parse(path, parser).getroot()
ra, rb = tree(sys.argv[1]), tree(sys.argv[2])
for parent in list(rb.iter()):
    for child in list(parent):
        is_added = (child.tag in ("link", "joint") and (child.get("name") in ("world", "tcp", "world_to_base_link", "tool_to_tcp"))) \
            or (child.tag is ET.Comment and child.text.startswith(" kincal:"))
        if is_added:
            parent.remove(child)
        if parent.tag == "joint" and parent.get("name") in ("j1", "j2", "j3") and child.tag == "origin":
            if parent.get("name") == "j3":
                parent.remove(child)
            else:
                for key in ("xyz", "rpy"):
                    child.attrib.pop(key, None)
for joint in ra.iter("joint"):
    if joint.get("name") in ("j1", "j2"):
        for key in ("xyz", "rpy"):
            joint.find("origin").attrib.pop(key, None)
def same(x, y, where):
    tail = lambda e: e.tail.strip() if e.tail and not e.tail.strip() else e.tail
    if x.tag != y.tag or x.attrib != y.attrib or x.text != y.text or tail(x) != tail(y) or len(x) != len(y):
        problems.append("tree differs at %s: %r %r %r vs %r %r %r" % (where, x.tag, x.attrib, (x.text or "")[:80], y.tag, y.attrib, (y.text or "")[:80]))
        return
    for k, (p, q) in enumerate(zip(x, y)):
        same(p, q, "%s/%s[%d]" % (where, p.tag if isinstance(p.tag, str) else "node", k))
same(ra, rb, "robot")
if ra.get("name") != "caf\u00e9bot":
    problems.append("the parser read the robot's name as %r" % ra.get("name"))
for p in problems:
    print("  " + p)
sys.exit(1 if problems else 0)
EOF
# Without corrections (every origin error and offset zero) no origin is touched: the export
# is the URDF, its header and the added elements.
"$kincal" export --model m.json --format urdf --out rich_nominal.urdf 2>e.txt
check "export of the URDF with everything, without corrections" 0 $? e.txt
py - rich.urdf rich_nominal.urdf <<'EOF' || bad "export of the URDF with everything, without corrections: more than the header and the added elements changed"
import re, sys
original = open(sys.argv[1], "rb").read()
exported = open(sys.argv[2], "rb").read()
exported = re.sub(rb"\n<!-- kincal export:[^\n]*?-->", b"", exported, count=1)
exported = re.sub(rb"  <!-- kincal: the measurement frame.*?</joint>\n.*?</joint>\n(?=</robot>)", b"", exported, count=1, flags=re.S)
sys.exit(0 if exported == original else 1)
EOF
if command -v check_urdf >/dev/null 2>&1; then
  check_urdf rich_out.urdf >/dev/null 2>e.txt
  check "check_urdf reads the export of the URDF with everything" 0 $? e.txt
fi

# ---- security: what kincal writes into the XML ----------------------------------------------
# A sensor name within the names policy that closes the comment it is written into.
urdf_imports "the arm" arm.urdf
py - <<'EOF'
import json
m = json.load(open("m.json"))
evil = "t--><evil/><!--x"
m["sensors"][0]["name"] = evil
m["free"] = [f.replace("tracker.", evil + ".") for f in m["free"]]
json.dump(m, open("evil.json", "w"), indent=2)
EOF
"$kincal" export --model evil.json --format urdf --out evil.urdf 2>e.txt
check "export with the sensor 't--><evil/><!--x'" 0 $? e.txt
py - <<'EOF' || bad "export with the sensor 't--><evil/><!--x': an element was injected"
import sys, xml.etree.ElementTree as ET
parser = ET.XMLParser(target=ET.TreeBuilder(insert_comments=True))
root = ET.parse("evil.urdf", parser).getroot()
tags = {e.tag for e in root.iter() if isinstance(e.tag, str)}
comments = [e.text for e in root.iter() if e.tag is ET.Comment]
sys.exit(0 if "evil" not in tags and any("t- ->" in c for c in comments) else print(tags, comments) or 1)
EOF

# File names with an escape character and a byte that is not UTF-8 are written as \xNN in the
# header comment, for an imported arm and a DH arm alike, and in the CSV's comment and the
# JSON's source (JSON holds UTF-8 only; its backslashes are escaped).
"$kincal" model --preset puma560 --out puma.json 2>/dev/null
odd=$(printf 'm\033[31m\377')
for model in corrected.json puma.json; do
  cp "$model" "$odd.json"
  for format in urdf csv json; do
    [ "$model/$format" = corrected.json/csv ] && continue # no DH table for an imported arm
    rm -f odd.out
    "$kincal" export --model "$odd.json" --format $format --out odd.out 2>e.txt
    check "export --format $format of '$model' under a name with ESC and 0xFF" 0 $? e.txt
    has odd.out 'm\\\\?x1B\[31m\\\\?xFF\.json' \
      "export --format $format of '$model' under a name with ESC and 0xFF: the name as \\xNN"
    py -c 'import sys; t = open("odd.out", "rb").read(); t.decode("utf-8"); sys.exit(b"\x1b" in t)' ||
      bad "export --format $format of '$model' under a name with ESC and 0xFF: raw ESC or not UTF-8"
  done
  rm -f "$odd.json"
done

# A root link whose name holds quotes and markup (a stand under the arm's base: the root's name
# is not recorded in the model file) reaches the added joint's attributes escaped.
urdf_arm arm.urdf
py - <<'EOF'
arm = open("arm.urdf").read()
stand = """<link name="b&quot;&lt;x&gt;&apos;&amp;"/>
  <joint name="stand" type="fixed"><parent link="b&quot;&lt;x&gt;&apos;&amp;"/><child link="base_link"/></joint>
  <link name="base_link"/>"""
open("quoted.urdf", "w").write(arm.replace('<link name="base_link"/>', stand, 1))
EOF
urdf_imports "a root link named 'b\"<x>'\''&'" quoted.urdf --base base_link
"$kincal" export --model m.json --format urdf --out quoted_out.urdf 2>e.txt
check "export of a root link named 'b\"<x>'\''&'" 0 $? e.txt
py - <<'EOF' || bad "export of a root link named 'b\"<x>'\''&': the world joint's child is not the root"
import sys, xml.etree.ElementTree as ET
root = ET.parse("quoted_out.urdf").getroot()
joint = [j for j in root.iter("joint") if j.find("parent").get("link") == "world"]
sys.exit(0 if len(joint) == 1 and joint[0].find("child").get("link") == "b\"<x>'&" else 1)
EOF
