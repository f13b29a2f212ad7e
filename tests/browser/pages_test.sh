#!/usr/bin/env bash
# The result pages in a real browser: makes two run folders (balloon_grasp cut to 8 s, and the
# bottle's hand-over cut to 10 s, each with its plots, panels and event markers), a small sweep
# folder (hover over 2 masses, 2 bounds of an envelope and 2 seeds, one envelope that always
# passes and one that fails at the tighter bound) and a folder run of two hover specs, then opens
# each index.html in headless Chromium twice: --dump-dom, whose DOM must hold the tables, the
# inlined <svg> plots and the verdicts, load nothing and link only to files that exist
# (tests/browser/page_check.py); and --screenshot, whose PNG must decode and not be blank, and for
# the sweep show its pass map's blue and vermillion cells. The sweep's map.svg, which its page
# links, must be an SVG document of a size a browser shows (page_check.py svg). Chromium's log
# must show no console message (the pages run no script, so any message is
# an error, and the pages' Content-Security-Policy turns every attempted load into one) and no
# file loaded but the page. A page that loads an image shows that the log check can fail.
# Chromium's profile, HOME and caches go into the test's temporary folder.
# Skips (exit 77) when chromium or python3 is not installed.
# Usage: pages_test.sh HILRIG SOURCE_DIR
set -euo pipefail
hilrig=$1
source_dir=$2
checks=$source_dir/tests/browser/page_check.py

command -v chromium >/dev/null ||
  { echo "SKIP: chromium is not installed (scripts/setup installs it)"; exit 77; }
command -v python3 >/dev/null || { echo "SKIP: python3 is not installed"; exit 77; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/home"
readonly width=1280 height=2000
# The pages' verdict colours (host/report/html_page.cc), which only their style sheet paints, and
# the map's pass and fail colours (host/report/grid_map.h).
readonly verdict='1A7F37|CF222E' map_blue=0072B2 map_vermillion=D55E00

# browse PAGE OUT LOG ARGS...: Chromium on PAGE with ARGS, standard output to OUT, its log to
# LOG. File loads are logged at verbosity 1 of file_url_loader_factory, console messages at INFO.
browse() {
  local page=$1 out=$2 log=$3
  shift 3
  HOME=$work/home XDG_CONFIG_HOME=$work/home/.config XDG_CACHE_HOME=$work/home/.cache \
    timeout 60 chromium --headless --no-sandbox --user-data-dir="$work/profile" \
    --no-first-run --disable-background-networking --disable-component-update --disable-sync \
    --disable-default-apps --hide-scrollbars --enable-logging=stderr --v=0 \
    --vmodule=file_url_loader_factory=1 "$@" "file://$page" >"$out" 2>"$log"
}

# log_problems PAGE LOG: what the log shows the page did beyond being shown.
log_problems() {
  grep -F ':CONSOLE' "$2" | sed 's/^/console: /' || true
  grep -F 'FileURLLoader::Start: ' "$2" | grep -vF "FileURLLoader::Start: file://$1" |
    sed 's/^/loaded: /' || true
}

failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}

# check_page PAGE MIN_SVGS COLOURS TEXT...: the DOM, the log and a screenshot of PAGE, which must
# show each of the space-separated COLOURS: a colour RRGGBB, or alternatives A|B of which one.
check_page() {
  local page=$1 min_svgs=$2 colours=$3 name problems
  shift 3
  name=$(basename "$(dirname "$page")")
  browse "$page" "$work/$name.dom" "$work/$name.log" --dump-dom ||
    fail "$page: chromium --dump-dom exited $?"
  python3 "$checks" dom "$page" "$work/$name.dom" "$min_svgs" "$@" || failures=$((failures + 1))
  grep -qF "FileURLLoader::Start: file://$page" "$work/$name.log" ||
    fail "$page: the log does not show the page's own load, so the log check sees nothing"
  browse "$page" /dev/null "$work/$name.shot.log" --screenshot="$work/$name.png" \
    --window-size="$width,$height" || fail "$page: chromium --screenshot exited $?"
  problems=$(log_problems "$page" "$work/$name.log"; log_problems "$page" "$work/$name.shot.log")
  [[ -z $problems ]] || fail "$page: $problems"
  [[ -s $work/$name.png ]] || { fail "$page: no screenshot written"; return; }
  # $colours unquoted: one argument per colour.
  python3 "$checks" png "$work/$name.png" "$width" "$height" $colours ||
    failures=$((failures + 1))
}

# run_scene NAME SPEC ARGS...: hilrig run of SPEC into $work/NAME; a verdict either way is fine.
run_scene() {
  local name=$1 spec=$2 status=0
  shift 2
  "$hilrig" run "$spec" --no-reference --out "$work/$name" "$@" >"$work/$name.out" 2>&1 ||
    status=$?
  ((status <= 1)) || { echo "FAIL: hilrig run $spec exited $status"; cat "$work/$name.out"; exit 1; }
}

# Run folders of two grasp scenes: balloon_grasp's grasp, lift and hold, and the bottle's
# hand-over. Each page shows the grasp force (true under the estimate), a panel per pad, the
# load, the position error, x, y and z against the reference (with clear_of_ground on z) and the
# top view (6 plots; the pad and trajectory panels are nested <svg>s: 6 + 6 + 3 = 15), with the
# timeline's events marked.
run_scene run "$source_dir/scenarios/balloon_grasp.textproto" --duration-s 8
check_page "$work/run/index.html" 15 "$verdict" "<h2>Envelopes</h2>" "<td>grasp_force</td>" \
  "<h2>Objects</h2>" "<td>real-time factor</td>" 'class="badge ' \
  "Grasp force: true (wide, light) and the DUT's estimate" ">true (plant)<" ">DUT estimate<" \
  ">Pad 0 (node 1)<" ">Pad 5 (node 6)<" ">decoded by the DUT<" ">grasp 0.6 N<" \
  ">setpoint (0, 0, 0.55) m<" ">Altitude z and its reference<" ">x (m)<" ">y (m)<" \
  "Top view: the path" 'class="marker-labels"'
run_scene bottle "$source_dir/scenarios/bottle_feedback.textproto" --duration-s 10
check_page "$work/bottle/index.html" 15 "$verdict" "<h2>Objects</h2>" ">grasp 3.5 N<" ">stand removed<" \
  "envelope clear_of_ground" ">Pad 3 (node 4)<" "Vertical load of the grasped object"

# A sweep folder with passing and failing cases, so that both colours, the failing cases'
# commands and the links to their run folders are on the page; over two axes, so that it has its
# pass map: the tight envelope fails at its first bound and passes at its second.
cat >"$work/hover.textproto" <<'SPEC'
name: "hover_pages"
vehicle { initial_position_m { z: 1 } }
simulation { duration_s: 1 }
envelopes { name: "altitude" signal: ALTITUDE_ERROR_M upper: 0.05 }
envelopes { name: "tight" signal: ALTITUDE_ERROR_M upper: 1e-9 }
SPEC
cat >"$work/sweep.textproto" <<'SPEC'
name: "hover_pages"
scenario: "hover.textproto"
seeds { count: 2 }
axis { path: "vehicle.mass_kg" list { value: 0.5 value: 0.6 } }
axis { path: "envelopes[1].upper" list { value: 1e-9 value: 1 } }
criterion { envelope: "altitude" min_pass_rate: 0.2 }
SPEC
sweep_status=0
"$hilrig" sweep "$work/sweep.textproto" --out "$work/sweep" --jobs 2 >"$work/sweep.out" 2>&1 ||
  sweep_status=$?
((sweep_status <= 1)) ||
  { echo "FAIL: hilrig sweep exited $sweep_status"; cat "$work/sweep.out"; exit 1; }
check_page "$work/sweep/index.html" 3 "$verdict $map_blue $map_vermillion" "<h2>Criteria</h2>" \
  "<h2>Envelopes</h2>" "<h2>Pass map</h2>" ">2/2</text>" ">0/2</text>" 'href="map.svg"' \
  "<h2>Worst values</h2>" "<h2>Cases that did not pass</h2>" "<code>" \
  'href="runs/case-0000000/index.html"'
# The map the page links, as a file of its own: the page draws the same map inline, so its
# screenshot above shows that Chromium renders it; here it must be a whole SVG document whose
# size (what an <img> of it would take as its natural size) is not zero.
python3 "$checks" svg "$work/sweep/map.svg" "$map_blue" "$map_vermillion" ||
  failures=$((failures + 1))
# A failing case's folder has its own page, which the sweep's page links to.
[[ -f $work/sweep/runs/case-0000000/index.html ]] || fail "no page in the failing case's folder"

# A folder run's page: the same hover spec passing and, with a bound it cannot keep, failing,
# in a file whose name needs percent-encoding in the link to its run folder.
mkdir -p "$work/folder"
cp "$work/hover.textproto" "$work/folder/hover.textproto"
sed 's/upper: 0.05/upper: 1e-9/' "$work/hover.textproto" >"$work/folder/hover #2.textproto"
folder_status=0
"$hilrig" run "$work/folder" --out "$work/suite" >"$work/suite.out" 2>&1 || folder_status=$?
((folder_status == 1)) ||
  { echo "FAIL: the folder run exited $folder_status, not 1"; cat "$work/suite.out"; exit 1; }
check_page "$work/suite/index.html" 0 "$verdict" "<h2>Scenarios</h2>" 'href="hover/index.html"' \
  'href="hover%20%232/index.html"' '<span class="badge fail">FAIL</span>'

# The log check can fail: a page with the same policy that tries to load an image.
mkdir -p "$work/canary"
cat >"$work/canary/index.html" <<'HTML'
<!DOCTYPE html><html><head><meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; style-src 'unsafe-inline'">
<title>canary</title></head><body><img src="missing.png" alt=""></body></html>
HTML
browse "$work/canary/index.html" /dev/null "$work/canary.log" --dump-dom || true
[[ -n $(log_problems "$work/canary/index.html" "$work/canary.log") ]] ||
  fail "a page that loads an image passes the log check: Chromium's log format changed?"

((failures == 0)) || exit 1
echo "PASS: the run, sweep and folder-run pages render in Chromium with their tables and plots, load nothing; the sweep's map.svg renders"
