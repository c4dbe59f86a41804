#!/usr/bin/env bash
# The calibration report for people opened in a real browser: a simulated campaign is
# calibrated with --html, headless Chromium loads the page from disk (no network: the
# page's Content-Security-Policy allows nothing but its own inline styles) and
#   --dump-dom  must hold every section and the five charts with their points and bars;
#   --screenshot must produce a picture that is not blank;
# and compare --html's page (the calibrated model against the truth): its sections, its two
# charts with their points, no raw JSON.
# Skipped (exit 77, with the reason) only when no chromium is installed; scripts/setup.sh
# installs Debian's chromium. Usage: html_report_browser_test.sh KINCAL [SCREENSHOT_COPY.png]
set -euo pipefail
kincal=$1
copy_to=${2:-}
browser=""
for candidate in chromium chromium-browser; do
  if command -v "$candidate" >/dev/null 2>&1; then browser=$candidate; break; fi
done
if [ -z "$browser" ]; then
  echo "skipped: chromium is not installed (scripts/setup.sh installs Debian's chromium)"
  exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$kincal" model --out "$dir/nominal.json"
"$kincal" simulate --model "$dir/nominal.json" --case 5 --seed 7 --write-data "$dir/measured.csv" >/dev/null
"$kincal" calibrate --model "$dir/nominal.json" --data "$dir/measured.csv" \
  --out "$dir/calibrated.json" --html "$dir/report.html" >/dev/null
flags=(--headless --no-sandbox --disable-gpu --no-first-run --disable-extensions
       --disable-background-networking --user-data-dir="$dir/profile" --hide-scrollbars)
fail() { echo "FAIL: $*"; exit 1; }

timeout 180 "$browser" "${flags[@]}" --dump-dom "file://$dir/report.html" >"$dir/dom.html" 2>"$dir/chromium.log" ||
  { cat "$dir/chromium.log"; fail "chromium --dump-dom failed"; }
for id in verdicts summary residuals parameters correlation identifiability outliers; do
  grep -q "<section id=\"$id\">" "$dir/dom.html" || fail "section '$id' missing from the rendered DOM"
done
svgs=$(grep -o '<svg' "$dir/dom.html" | wc -l)
[ "$svgs" -eq 5 ] || fail "expected 5 charts in the rendered DOM, found $svgs"
circles=$(grep -o '<circle' "$dir/dom.html" | wc -l)
[ "$circles" -ge 60 ] || fail "expected at least 60 plotted points, found $circles"
grep -q '<script' "$dir/dom.html" && fail "the page holds a script"

timeout 180 "$browser" "${flags[@]}" --window-size=1200,2400 --screenshot="$dir/report.png" \
  "file://$dir/report.html" >"$dir/shot.log" 2>&1 || { cat "$dir/shot.log"; fail "chromium --screenshot failed"; }
[ -f "$dir/report.png" ] || fail "no screenshot written"
head -c 8 "$dir/report.png" | od -An -tx1 | grep -q '89 50 4e 47' || fail "the screenshot is not a PNG"
size=$(stat -c %s "$dir/report.png")
# A blank 1200 x 2400 page compresses to about 10 KB; text and charts make it much larger.
[ "$size" -gt 60000 ] || fail "the screenshot is only $size bytes: the page looks blank"
if [ -n "$copy_to" ]; then cp "$dir/report.png" "$copy_to"; fi

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
echo "html report renders in $browser: 7 sections, $svgs charts, $circles points, screenshot $size bytes"
