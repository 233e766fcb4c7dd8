#!/usr/bin/env bash
# The lessons, side by side: on a fresh Debian 12 machine, install what is needed, build, then
# for the Cornell box with a mirror and a glass sphere, Whitted's scene and Kajiya's:
#   1. take the converged reference, rendered by the estimator that is unbiased for the scene:
#      lesson 5 where lesson 4 says it misses light or finds caustics only by chance (a point
#      light, a mirror or glass), else lesson 4. The default page's three are shipped in
#      references/ with their provenance (scripts/references.sh; the test ShippedReferences
#      checks them against today's code); other settings render their own, cached in out/ while
#      the scene, the renderer and the settings are unchanged;
#   2. run the five lessons at equal time budgets, recording error against time;
#   3. run lesson 3's five estimators, lesson 4 without next-event estimation, lesson 5's
#      light tracing alone and lesson 6's pm, ppm and vpl (all of independent samples), and
#      lesson 4 with its default, stratified sampler; name the run of the lowest error;
#   4. plot MSE against seconds, log-log, every run on one chart (gnuplot: SVG and PNG);
#   5. estimate each run's converged error, its squared bias (MSE minus the variances of the run
#      and of the reference), by batch means over 8 renders with seeds of their own, each of an
#      eighth of the run's samples (scripts/converged_error.sh), with the reasons its model gives;
#   6. write out/index.html: a static page (no server needed) with the images side by side, a
#      flip/slider comparison, the error images, the chart, the converged-bias table and a table
#      of the figures.
# Usage: scripts/lessons.sh [--quick | --thorough | --references]
#   default: ~256 px images, 4 s per run, the shipped references (9 min 38 s on 2 idle cores
#   with three scenes and six lessons, the batch means of the converged-error table included;
#   the door scene and lesson 7 add to it); --quick: tiny images, 0.3 s per run (66 s with
#   three scenes, its references included); --thorough: 512 px, 30 s per run, and
#   its own references (8192 spp, rendered once and cached in out/ with their provenance);
#   --references: the default page, re-rendering the shipped references in references/ first
#   (with new provenance files; about 6 minutes more on 2 idle cores).
set -euo pipefail

MODE="${1:-default}"
case "$MODE" in
    default | --references) SIZE=256; BUDGET=4; REFERENCE_SPP=1024 ;;
    --quick) SIZE=64; BUDGET=0.3; REFERENCE_SPP=256 ;;
    --thorough) SIZE=512; BUDGET=30; REFERENCE_SPP=8192 ;;
    *) echo "usage: scripts/lessons.sh [--quick | --thorough | --references]" >&2; exit 2 ;;
esac

if [ "${LESSONS_SKIP_SETUP:-0}" = 1 ]; then
    ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
    BUILD="${BUILD_DIR:-$ROOT/build}"
else
    source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
    install_missing_packages gnuplot-nox
    build_suite
fi
OUT="${LESSONS_OUT:-$ROOT/out}"
mkdir -p "$OUT"
cd "$ROOT"
BIN="$BUILD/bin"
# field, list_field, reference_probe, shipped_reference_fits, render_reference
source "$ROOT/scripts/references.sh"
# json_number, batch_converged_error (the converged-bias table's batch means over seeds)
source "$ROOT/scripts/converged_error.sh"

# Runs: name | lesson | extra flags | label on the chart and in the table. First every lesson of
# the registry (chapters/lessons.txt) with its defaults, named lessonN; then the estimators the
# lessons compare.
RUNS=()
LESSONS=()
while IFS='|' read -r folder label _; do
    folder="$(echo "$folder" | tr -d ' ')"
    case "$folder" in [0-9][0-9]_*) ;; *) continue ;; esac  # NN_name; comments and blanks
    name="lesson$((10#${folder%%_*}))"
    LESSONS+=("$name")
    # Independent samples (--sampler independent): the convergence rate the lecture derives
    # (MSE ~ 1/N), and per-pixel variances that estimate the noise, which the bias table needs.
    RUNS+=("$name|$folder|--sampler independent|$(echo "$label" | sed 's/^ *//; s/ *$//')")
done < "$ROOT/chapters/lessons.txt"
RUNS+=(
    "estimator_uniform|03_reflection_equation|--estimator uniform --sampler independent|3 uniform"
    "estimator_cosine|03_reflection_equation|--estimator cosine --sampler independent|3 cosine"
    "estimator_brdf|03_reflection_equation|--estimator brdf --sampler independent|3 BRDF"
    "estimator_light|03_reflection_equation|--estimator light --sampler independent|3 light"
    "lesson4_plain|04_rendering_equation|--plain --sampler independent|4 plain (no NEE)"
    "lesson5_light_tracing|05_bidirectional|--light-tracing --sampler independent|5 light tracing alone"
    # Lesson 6's density estimates: a fixed radius (its bias stays) and a shrinking one.
    "lesson6_pm|06_photon_mapping|--method pm --sampler independent|6 photon mapping (fixed radius)"
    "lesson6_ppm|06_photon_mapping|--method ppm --sampler independent|6 progressive photon mapping"
    # Instant radiosity: the same light subpaths' vertices connected as virtual lights (capped).
    "lesson6_vpl|06_photon_mapping|--method vpl --sampler independent|6 instant radiosity (virtual lights)"
    # The lessons' default sampler: stratified, its error falls faster than 1/N on the same chart.
    "lesson4_stratified|04_rendering_equation|--sampler kronecker|4 stratified (kronecker, the default)"
)
SCENES=("cornell_spheres|The Cornell box with a mirror and a glass sphere|$SIZE|$SIZE"
        "whitted_1979|Whitted 1979: spheres and checkerboard|$((SIZE * 4 / 3))|$SIZE"
        "kajiya_1986|Kajiya 1986: grey objects, green glass balls, a red base|$((SIZE * 4 / 3))|$SIZE"
        # Lit only through a door's gap: lesson 4, which renders its reference, is a field of
        # fireflies here at the others' sample count, so it takes four times as many
        # (--thorough's 8192 spp are already eight times the default's).
        "door_ajar|A room lit through a door left ajar (after Veach and Guibas 1997)|$((SIZE * 3 / 2))|$SIZE|4")

sections=""
best_rows=""
bias_header="<tr><th>lesson</th>"
declare -A bias_cell
for entry in "${SCENES[@]}"; do
    IFS='|' read -r scene title width height ref_factor <<< "$entry"
    [ "$MODE" = --thorough ] && ref_factor=1
    ref_spp=$((REFERENCE_SPP * ${ref_factor:-1}))
    dir="$OUT/$scene"
    mkdir -p "$dir"
    size="--width $width --height $height"

    # 1. The reference, from the estimator that is unbiased for this scene (reference_probe:
    #    lesson 4's report says whether it is biased here or finds caustics only by chance).
    reference_probe "$scene" "$dir"
    ref_lesson="$REF_LESSON"
    ref_why="$REF_WHY"
    shipped="$ROOT/references/$scene"
    [ "$MODE" = --references ] &&
        render_reference "$scene" "$ref_lesson" "$width" "$height" "$ref_spp" "$shipped"
    reference_dir=""
    if { [ "$MODE" = default ] || [ "$MODE" = --references ]; }; then
        if shipped_reference_fits "$shipped/reference.toml" "$ref_lesson" "$width" "$height" \
            "$ref_spp" "$SCENE_FILES"; then
            reference_dir="$shipped"
            ref_from="shipped in references/$scene, rendered at commit $(toml_field "$shipped/reference.toml" commit | cut -c1-7) (its provenance: reference.toml there)"
            echo "lessons: $scene: the shipped reference ($ref_spp spp, $ref_lesson, references/$scene)"
        else
            echo "lessons: $scene: the shipped reference does not fit (scene files, size or lesson changed): rendering one"
        fi
    fi
    if [ -z "$reference_dir" ]; then
        reference_dir="$dir"
        ref_from="rendered by scripts/lessons.sh $MODE (its provenance: $scene/reference.toml beside this page)"
        key="$(cat "scenes/$scene.toml" "$BIN/$ref_lesson" | sha256sum | cut -c1-16)-$ref_lesson-$width-$height-$ref_spp"
        if [ -f "$dir/reference.exr" ] && [ -f "$dir/reference_variance.exr" ] && [ "$(cat "$dir/reference.key" 2>/dev/null)" = "$key" ]; then
            echo "lessons: $scene: reusing the reference ($ref_spp spp, $ref_lesson, out/$scene)"
        else
            render_reference "$scene" "$ref_lesson" "$width" "$height" "$ref_spp" "$dir"
            echo "$key" > "$dir/reference.key"
        fi
    fi
    reference="$reference_dir/reference.exr"
    reference_variance="$reference_dir/reference_variance.exr"
    # The page shows it beside the runs.
    [ "$reference_dir" = "$dir" ] || cp "$reference_dir/reference.png" "$dir/reference.png"

    # 2-3. Every run with the same time budget, recording error against time.
    plot_lines=""
    best_mse=""
    best_label=""
    rows=""
    bias_rows=""
    bias_header+="<th>$title</th>"
    gallery=""
    options=""
    for run in "${RUNS[@]}"; do
        IFS='|' read -r name lesson flags label <<< "$run"
        "$BIN/$lesson" --scene "scenes/$scene.toml" $size $flags --time "$BUDGET" --seed 1 \
            --reference "$reference" --convergence "$dir/$name.csv" --out "$dir/$name" \
            --report "$dir/$name.json" --variance "$dir/${name}_variance" --quiet
        "$BIN/compare" "$dir/$name.exr" "$reference" --out "$dir/$name" \
            --variance "$dir/${name}_variance.exr" \
            --reference-variance "$reference_variance" > "$dir/$name.compare.json" 2> /dev/null
        # 5. Its converged error by batch means: CONVERGED_ERROR_BATCHES renders of independent
        #    samples with seeds of their own, each of an eighth of this run's samples, and at
        #    least CONVERGED_ERROR_MIN_SPP (converged_error.sh says why). A stratified run's own
        #    variance is not its error: n/a.
        case "$flags" in
            *"--sampler independent"*)
                batch_spp=$(( $(field "$dir/$name.json" spp) / CONVERGED_ERROR_BATCHES ))
                [ "$batch_spp" -ge "$CONVERGED_ERROR_MIN_SPP" ] || batch_spp=$CONVERGED_ERROR_MIN_SPP
                bias2="$(batch_converged_error "$lesson" "scenes/$scene.toml" "$batch_spp" \
                    "$reference_dir" "$dir/$name" $size ${flags/--sampler independent/})" ;;
            *) bias2="n/a (stratified)" ;;
        esac
        echo "lessons: $scene: $label: $(field "$dir/$name.json" spp) spp in $(field "$dir/$name.json" seconds) s, mse $(field "$dir/$name.json" mse), converged mse (bias^2) $bias2"
        why="$(list_field "$dir/$name.json" bias)"
        # Biased but consistent (a shrinking radius): the bias goes with more time.
        [ "$(field "$dir/$name.json" consistent)" = true ] && [ "$(field "$dir/$name.json" biased)" = true ] &&
            why="consistent (the bias shrinks as it renders): $why"
        # Lesson 6: the photons' radius, from the first pass to the last (the bias falls with it).
        radius="$(json_number "$dir/$name.json" radius_reached)"
        [ -n "$radius" ] && why="${why:+$why; }photon radius $(json_number "$dir/$name.json" radius_first) to $radius"
        bias_rows+="<tr><td>$label</td><td>$bias2</td><td>$(field "$dir/$name.json" mse)</td><td class=\"why\">${why:-unbiased here}</td></tr>"
        bias_cell["$name|$scene"]="$bias2"
        mse="$(field "$dir/$name.json" mse)"
        # A number, or not a candidate (a failed comparison leaves none, or nan).
        if [[ "$mse" =~ ^[0-9.]+([eE][-+]?[0-9]+)?$ ]] &&
            { [ -z "$best_mse" ] || awk -v a="$mse" -v b="$best_mse" 'BEGIN { exit !(a + 0 < b + 0) }'; }; then
            best_mse="$mse"
            best_label="$label"
        fi
        plot_lines+="'$dir/$name.csv' using 1:3 with linespoints title '$label', "
        rows+="<tr><td>$label</td><td>$(field "$dir/$name.json" seconds)</td><td>$(field "$dir/$name.json" spp)</td><td>$(field "$dir/$name.json" mrays_per_second)</td><td>$(field "$dir/$name.json" mse)</td><td>$(field "$dir/$name.json" relmse)</td><td>$(field "$dir/$name.json" efficiency)</td></tr>"
        gallery+="<figure><img src=\"$scene/$name.png\" alt=\"$label\"><figcaption>$label</figcaption></figure>"
        options+="<option value=\"$scene/$name.png\">$label</option>"
    done
    options+="<option value=\"$scene/reference.png\">reference</option>"
    echo "lessons: $scene: the lowest error at $BUDGET s: $best_label (mse $best_mse)"
    best_rows+="<tr><td>$title</td><td>$best_label</td><td>$best_mse</td></tr>"

    # 4. MSE against seconds, log-log, every run on one chart.
    for terminal in "svg size 960,600 dynamic" "pngcairo size 960,600"; do
        extension="${terminal%% *}"; extension="${extension/pngcairo/png}"
        gnuplot <<EOF
set terminal $terminal
set output '$dir/convergence.$extension'
set datafile separator ','
set logscale xy
set xlabel 'rendering time (seconds)'
set ylabel 'MSE against the reference'
set title "$title"
set key outside right
set grid
plot ${plot_lines%, }
EOF
    done

    # 5. This scene's part of the page.
    lessons_row=""
    for name in "${LESSONS[@]}"; do
        lessons_row+="<figure><img src=\"$scene/$name.png\" alt=\"$name\"><figcaption>$name</figcaption></figure>"
    done
    errors=""
    for run in "${RUNS[@]}"; do
        IFS='|' read -r name lesson flags label <<< "$run"
        errors+="<figure><img src=\"$scene/${name}_error.png\" alt=\"error of $label\"><figcaption>$label</figcaption></figure>"
    done
    sections+="
<section>
<h2>$title</h2>
<h3>The ${#LESSONS[@]} lessons, ${BUDGET} s each</h3>
<p class=\"best\">The lowest error at ${BUDGET} s on this scene: <b>$best_label</b> (MSE $best_mse; every run's in the figures below).</p>
<div class=\"row\">$lessons_row<figure><img src=\"$scene/reference.png\" alt=\"reference\"><figcaption>reference ($ref_spp spp)</figcaption></figure></div>
<p>The reference: $ref_why; $ref_spp samples per pixel, another seed than the runs; $ref_from.</p>
<h3>Compare any two</h3>
<div class=\"compare\" data-scene=\"$scene\">
<select class=\"left\">$options</select> <select class=\"right\">$options</select>
<button class=\"flip\">flip</button> <input class=\"slider\" type=\"range\" min=\"0\" max=\"100\" value=\"50\">
<div class=\"stack\"><img class=\"under\" src=\"$scene/lesson4.png\" alt=\"right image\"><img class=\"over\" src=\"$scene/lesson1.png\" alt=\"left image\"></div>
</div>
<h3>Error against the reference (RMS over channels; dark 0, yellow: the 99th percentile, scale under each)</h3>
<div class=\"row\">$errors</div>
<h3>Error against time</h3>
<img class=\"plot\" src=\"$scene/convergence.svg\" alt=\"MSE against seconds\">
<p>Every run but one draws independent random numbers (<code>--sampler independent</code>): an
unbiased one's MSE falls as 1/N, a line of slope -1 here. The lessons' default sampler stratifies each pixel's
samples (<code>--sampler kronecker</code>, the line \"4 stratified\"): the same estimator as lesson 4,
unbiased, whose error falls faster, because its samples cannot clump.</p>
<h3>Converged error: what more time cannot fix</h3>
<p>The squared bias, the MSE each run would converge to: MSE minus the variances of the run and of
the reference (both measured per pixel, of independent samples), averaged over
$CONVERGED_ERROR_BATCHES renders with seeds of their own, each of an eighth of the run's samples (at least $CONVERGED_ERROR_MIN_SPP),
with the standard error of that mean (batch means: a pass's light paths light many pixels at once,
so the pixels of one render are not independent). \"0 within noise\" where it lies within
Student's t (0.05, two-sided) standard errors of 0, as an unbiased estimator's does, of either sign;
the model's own reasons beside it. For the photon methods it is the bias at an eighth of the
passes, their radius larger than at the budget.</p>
<table class=\"bias\"><tr><th>run</th><th>converged MSE (bias&sup2;)</th><th>MSE at ${BUDGET} s</th><th>why (the model's report)</th></tr>$bias_rows</table>
<h3>Figures</h3>
<table><tr><th>run</th><th>seconds</th><th>spp</th><th>Mrays/s</th><th>MSE</th><th>relMSE</th><th>efficiency 1/(MSE s)</th></tr>$rows</table>
<h3>All runs</h3>
<div class=\"row\">$gallery</div>
</section>"
done

# The converged-bias table over every scene: one row per lesson.
bias_table="$bias_header</tr>"
for name in "${LESSONS[@]}"; do
    bias_table+="<tr><td>$name</td>"
    for entry in "${SCENES[@]}"; do
        IFS='|' read -r scene _ <<< "$entry"
        bias_table+="<td>${bias_cell["$name|$scene"]}</td>"
    done
    bias_table+="</tr>"
done

cat > "$OUT/index.html" <<EOF
<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Illumination models, lesson by lesson</title>
<style>
body { font-family: sans-serif; margin: 2em; max-width: 1400px; }
.row { display: flex; flex-wrap: wrap; gap: 8px; }
figure { margin: 0; } figure img { width: 256px; display: block; } figcaption { font-size: 0.85em; }
.stack { position: relative; display: block; width: 512px; margin-top: 6px; }
.stack img { width: 512px; display: block; } .stack .over { position: absolute; top: 0; left: 0; }
.plot { max-width: 960px; width: 100%; }
table { border-collapse: collapse; } td, th { border: 1px solid #aaa; padding: 2px 8px; text-align: right; }
td.why { text-align: left; font-size: 0.85em; }
</style></head>
<body>
<h1>Illumination models, lesson by lesson</h1>
<p>Each lesson rendered the same scene for the same time (${BUDGET} s on $(nproc) cores), and its error was
measured against a converged global-illumination reference it did not produce. Unbiased Monte Carlo
estimators fall on a line of slope -1 in the log-log chart (MSE proportional to 1/time); ray casting and
Whitted's model flatten at their bias: they converge, but to a different image.
Generated by <code>scripts/lessons.sh $MODE</code> on $(date -u +%Y-%m-%d).</p>
<h2>Which method wins where</h2>
<p>For each scene, the run with the lowest MSE against the reference after ${BUDGET} s (all runs
below, lessons and estimators alike, one run each at seed 1: a near tie can go either way between
runs).</p>
<table><tr><th>scene</th><th>lowest error at ${BUDGET} s</th><th>its MSE</th></tr>$best_rows</table>
<h2>Converged error of each lesson (squared bias, against the unbiased reference)</h2>
<p>"Whitted is wrong" as a number: the MSE each lesson converges to, however long it runs. Each
scene's section below says which estimator rendered its reference and why, and each lesson's
reasons.</p>
<table>$bias_table</table>
$sections
<script>
for (const box of document.querySelectorAll('.compare')) {
  const left = box.querySelector('.left'), right = box.querySelector('.right');
  const over = box.querySelector('.over'), under = box.querySelector('.under');
  const slider = box.querySelector('.slider');
  left.value = box.dataset.scene + '/lesson1.png'; right.value = box.dataset.scene + '/lesson4.png';
  const update = () => { over.src = left.value; under.src = right.value;
    over.style.clipPath = 'inset(0 ' + (100 - slider.value) + '% 0 0)'; };
  left.onchange = right.onchange = slider.oninput = update;
  box.querySelector('.flip').onclick = () => { [left.value, right.value] = [right.value, left.value]; update(); };
  update();
}
// For tests: after loading, record how many images loaded and failed.
window.addEventListener('load', () => {
  const images = [...document.images];
  document.body.dataset.imagesLoaded = images.filter(i => i.complete && i.naturalWidth > 0).length;
  document.body.dataset.imagesFailed = images.filter(i => !(i.complete && i.naturalWidth > 0)).length;
});
</script>
</body></html>
EOF
echo "lessons: done; open $OUT/index.html"
