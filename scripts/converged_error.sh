#!/usr/bin/env bash
# A run's converged error, its squared bias, by batch means over independent seeds: the lessons
# page's converged-bias table (scripts/lessons.sh) and its test (tests/converged_error_test.sh).
# Source it after setting BIN (the lessons' executables and compare).
#
# One render's bias2 from `compare --variance` (per pixel: d^2 less the variances of the image's
# mean and of the reference's, averaged over the pixels) is an unbiased estimate of the squared
# bias when the renders draw independent samples (--sampler independent: then the film's
# per-pixel variance is that of its mean). Its error is another matter: a pass's light subpaths,
# photons or virtual lights light many pixels at once, so the pixels' errors are correlated, and
# fireflies make them heavy-tailed; a standard error that takes the pixels as independent
# understates it (on Whitted's scene, lesson 5 at 341 x 256 and 40 spp, seeds 1 to 6, against the
# shipped reference: 0.00014 to 0.00024, against a spread of 0.00026 over the six; each
# `build/bin/05_bidirectional --scene scenes/whitted_1979.toml --width 341 --height 256 --spp 40
# --seed S --sampler independent --variance V`, then `build/bin/compare` with both variances). Renders with different seeds are independent
# whatever the estimator, so the mean of K renders' bias2 has the standard error sd / sqrt(K), and
# a mean within t (Student's, K - 1 degrees of freedom, two-sided 0.05) standard errors of 0 is an
# unbiased estimator's.

# A number field of compare's one-line JSON.
json_number() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1"; }

CONVERGED_ERROR_BATCHES=8
# The fewest samples per pixel of a batch. With very few, a pixel's sample variance of a
# heavy-tailed estimator (fireflies) is itself so heavy-tailed that the mean of e over the pixels
# falls mostly below its expectation: lesson 5 on Kajiya's scene at 341 x 256, batches of 2 spp,
# gave -0.00526 +- 0.0019; of 8 spp, 0.00035 +- 0.0013 (batch_converged_error 05_bidirectional
# scenes/kajiya_1986.toml SPP references/kajiya_1986 PREFIX --width 341 --height 256).
CONVERGED_ERROR_MIN_SPP=8
CONVERGED_ERROR_SEED=2000000  # batch k renders with seed CONVERGED_ERROR_SEED + k

# batch_converged_error LESSON SCENE_FILE SPP REFERENCE_DIR OUT_PREFIX FLAGS...: renders
# CONVERGED_ERROR_BATCHES images of SPP samples per pixel (independent samples, seeds of their
# own), compares each with REFERENCE_DIR/reference.exr (and its variance), and prints
# "B ± SE" or "0 within noise (B ± SE)"; "?" if a render failed. FLAGS: the run's own (size,
# method...), passed to the lesson as they are.
batch_converged_error() {
    local lesson="$1" scene_file="$2" spp="$3" reference_dir="$4" prefix="$5"
    shift 5
    local values="" k
    for k in $(seq 1 "$CONVERGED_ERROR_BATCHES"); do
        "$BIN/$lesson" --scene "$scene_file" "$@" --spp "$spp" --sampler independent \
            --seed $((CONVERGED_ERROR_SEED + k)) --out "${prefix}_batch" \
            --variance "${prefix}_batch_variance" --quiet > /dev/null 2>&1 || { echo "?"; return; }
        "$BIN/compare" "${prefix}_batch.exr" "$reference_dir/reference.exr" \
            --variance "${prefix}_batch_variance.exr" \
            --reference-variance "$reference_dir/reference_variance.exr" \
            > "${prefix}_batch.compare.json" 2> /dev/null || { echo "?"; return; }
        local value
        value="$(json_number "${prefix}_batch.compare.json" bias2)"
        [[ "$value" =~ ^-?[0-9.]+([eE][-+]?[0-9]+)?$ ]] || { echo "?"; return; }
        values+="$value "
    done
    rm -f "${prefix}_batch.exr" "${prefix}_batch.png" "${prefix}_batch_variance.exr" \
        "${prefix}_batch.compare.json"
    batch_mean_and_error $values
}

# batch_mean_and_error V1 V2 ...: the mean of the values and its standard error, as
# batch_converged_error prints them (t: the two-sided 0.05 quantile of Student's t).
batch_mean_and_error() {
    echo "$@" | awk '{
        k = NF; m = 0; for (i = 1; i <= k; ++i) m += $i / k
        ss = 0; for (i = 1; i <= k; ++i) ss += ($i - m) * ($i - m)
        se = k > 1 ? sqrt(ss / (k - 1) / k) : 0
        split("12.706 4.303 3.182 2.776 2.571 2.447 2.365 2.306 2.262 2.228", t, " ")
        q = k - 1 <= 10 ? t[k - 1] : 2.0  # (about right to 60 degrees of freedom; K is 8)
        if (k < 2) { print "?"; exit }
        if (m < 0 ? -m <= q * se : m <= q * se) printf "0 within noise (%.3g ± %.2g)\n", m, se
        else printf "%.3g ± %.2g\n", m, se
    }'
}
