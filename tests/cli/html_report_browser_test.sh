#!/usr/bin/env bash
# The pages for people opened in a real browser: a simulated campaign is calibrated with
# --html (and --target, --sensitivity), headless Chromium loads the page from disk (no
# network: the page's Content-Security-Policy allows nothing but its own inline styles) and
#   --dump-dom  must hold every section and the seven charts with their points and bars;
#   --screenshot must produce a picture that is not blank;
# and the pages of validate, design, observability and compare --html the same way: each
# one's sections, its number of charts and of plotted points, no script and no raw JSON.
# Skipped (exit 77, with the reason) only when no chromium is installed; scripts/setup.sh --all
# installs Debian's chromium. Usage: html_report_browser_test.sh KINCAL [SCREENSHOT_COPY.png]
set -euo pipefail
kincal=$1
copy_to=${2:-}
browser=""
for candidate in chromium chromium-browser; do
  if command -v "$candidate" >/dev/null 2>&1; then browser=$candidate; break; fi
done
if [ -z "$browser" ]; then
  echo "skipped: chromium is not installed (scripts/setup.sh --all installs Debian's chromium)"
  exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$kincal" model --out "$dir/nominal.json"
"$kincal" simulate --model "$dir/nominal.json" --case 5 --seed 7 --write-data "$dir/measured.csv" >/dev/null
"$kincal" calibrate --model "$dir/nominal.json" --data "$dir/measured.csv" \
  --out "$dir/calibrated.json" --json "$dir/report.json" --html "$dir/report.html" \
  --target 0.1mm --sensitivity >/dev/null && status=0 || status=$?
# The 0.1 mm target is not met: "do not load it", exit 3, every output written.
[ "$status" = 3 ] || { echo "FAIL: calibrate --target exited $status, expected 3"; exit 1; }
flags=(--headless --no-sandbox --disable-gpu --no-first-run --disable-extensions
       --disable-background-networking --user-data-dir="$dir/profile" --hide-scrollbars)
fail() { echo "FAIL: $*"; exit 1; }

timeout 180 "$browser" "${flags[@]}" --dump-dom "file://$dir/report.html" >"$dir/dom.html" 2>"$dir/chromium.log" ||
  { cat "$dir/chromium.log"; fail "chromium --dump-dom failed"; }
for id in verdicts summary residuals parameters correlation identifiability outliers pose-accuracy sensitivity; do
  grep -q "<section id=\"$id\">" "$dir/dom.html" || fail "section '$id' missing from the rendered DOM"
done
# Residuals, histogram, corrections, correlation, singular values, the predicted pose error
# over the workspace, the sensitivity bars.
svgs=$(grep -o '<svg' "$dir/dom.html" | wc -l)
[ "$svgs" -eq 7 ] || fail "expected 7 charts in the rendered DOM, found $svgs"
# 60 residuals, 24 corrections, 24 singular values, 2 x 200 workspace samples.
circles=$(grep -o '<circle' "$dir/dom.html" | wc -l)
[ "$circles" -ge 508 ] || fail "expected at least 508 plotted points, found $circles"
grep -q '<script' "$dir/dom.html" && fail "the page holds a script"
grep -q '{"' "$dir/dom.html" && fail "raw JSON in the report"
grep -q 'does not meet the 0.1 mm target' "$dir/dom.html" || fail "no verdict against --target"
grep -q 'measure no point of the mechanism' "$dir/dom.html" || fail "no note on what a gauge cannot show"

timeout 180 "$browser" "${flags[@]}" --window-size=1200,2400 --screenshot="$dir/report.png" \
  "file://$dir/report.html" >"$dir/shot.log" 2>&1 || { cat "$dir/shot.log"; fail "chromium --screenshot failed"; }
[ -f "$dir/report.png" ] || fail "no screenshot written"
head -c 8 "$dir/report.png" | od -An -tx1 | grep -q '89 50 4e 47' || fail "the screenshot is not a PNG"
size=$(stat -c %s "$dir/report.png")
# A blank 1200 x 2400 page compresses to about 10 KB; text and charts make it much larger.
[ "$size" -gt 60000 ] || fail "the screenshot is only $size bytes: the page looks blank"
if [ -n "$copy_to" ]; then cp "$dir/report.png" "$copy_to"; fi

# A page opened in Chromium: its sections in order, its number of charts, at least so many
# plotted points, no script, no raw JSON.  check_page NAME FILE "IDS" SVGS MIN_CIRCLES
check_page() {
  local name=$1 file=$2 ids=$3 want_svgs=$4 want_circles=$5
  timeout 180 "$browser" "${flags[@]}" --dump-dom "file://$file" >"$dir/$name.dom" 2>"$dir/chromium.log" ||
    { cat "$dir/chromium.log"; fail "chromium --dump-dom of the $name page failed"; }
  local found
  found=$(grep -o '<section id="[^"]*"' "$dir/$name.dom" | sed 's/<section id="//; s/"$//' | tr '\n' ' ')
  [ "$found" = "$ids " ] || fail "$name page: sections '$found', expected '$ids '"
  local n
  n=$(grep -o '<svg' "$dir/$name.dom" | wc -l)
  [ "$n" -eq "$want_svgs" ] || fail "$name page: expected $want_svgs charts, found $n"
  n=$(grep -o '<circle' "$dir/$name.dom" | wc -l)
  [ "$n" -ge "$want_circles" ] || fail "$name page: expected at least $want_circles points, found $n"
  grep -q '<script' "$dir/$name.dom" && fail "$name page holds a script"
  grep -q '{"' "$dir/$name.dom" && fail "$name page: raw JSON in the page"
  return 0
}
# validate: the calibration data as held-out data (the page matters here, not the verdict):
# 60 residuals, 60 before and 60 after.
"$kincal" validate --model "$dir/calibrated.json" --data "$dir/measured.csv" --report "$dir/report.json" \
  --target 0.1mm --html "$dir/validate.html" >/dev/null || true
check_page validate "$dir/validate.html" "verdicts summary readings residuals position" 2 180
grep -q 'Cannot say whether the pose meets the 0.1 mm target' "$dir/validate.dom" || fail "validate page: no target verdict"
# design: 3 x 200 workspace samples, the 30 chosen among the candidates, the exchange passes.
"$kincal" design --model "$dir/nominal.json" --poses 30 --candidates 300 --noise-std 0.0072mm \
  --out "$dir/template.csv" --target 1mm --html "$dir/design.html" >/dev/null
check_page design "$dir/design.html" "verdicts summary prediction configurations progress parameters search" 3 930
# observability: 24 singular values and the sensitivity bars.
"$kincal" observability --model "$dir/nominal.json" --poses 40 --sensitivity --html "$dir/observability.html" >/dev/null
check_page observability "$dir/observability.html" "verdicts summary identifiability sensitivity" 2 24

# compare --html: the calibrated model against the simulation's truth.
"$kincal" compare --truth "$dir/measured.truth.json" --model "$dir/calibrated.json" \
  --html "$dir/compare.html" >/dev/null
timeout 180 "$browser" "${flags[@]}" --dump-dom "file://$dir/compare.html" >"$dir/cdom.html" 2>"$dir/chromium.log" ||
  { cat "$dir/chromium.log"; fail "chromium --dump-dom of the compare page failed"; }
for id in verdicts pose parameters; do
  grep -q "<section id=\"$id\">" "$dir/cdom.html" || fail "compare page: section '$id' missing"
done
csvgs=$(grep -o '<svg' "$dir/cdom.html" | wc -l)
[ "$csvgs" -eq 2 ] || fail "compare page: expected 2 charts (pose and parameter errors), found $csvgs"
ccircles=$(grep -o '<circle' "$dir/cdom.html" | wc -l)
[ "$ccircles" -ge 224 ] || fail "compare page: expected 200 pose and 24 parameter points, found $ccircles"
grep -q '{"' "$dir/cdom.html" && fail "compare page: raw JSON in the page"
echo "pages render in $browser: report with $svgs charts and $circles points (screenshot $size bytes), validate, design, observability and compare pages"
