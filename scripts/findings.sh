#!/usr/bin/env bash
# Reruns the measurements of docs/findings/, in the order the pages list them.
# Each step runs the commands its page shows above its tables and writes what
# they print (and the CSVs, reports and JSON they write) under
# out/findings/STEP/; a step's log is out/findings/STEP/log.txt.  Compare the
# outputs with the page by hand, then update the page, its date and machine.
#
#   ./scripts/findings.sh             every step (hours on 2 cores: the sweeps dominate)
#   ./scripts/findings.sh STEP...     only these steps, e.g. bundled-scenes cap-arrangement
#   ./scripts/findings.sh --list      the steps, with the page each one feeds
#
# Needs a Release build (./scripts/build.sh, with the benchmarks) and, for the
# real-GL steps, a headless EGL driver.
set -euo pipefail
cd "$(dirname "$0")/.."
n=./build/nearcap
bench=./build/analysis/benchmarks
top=out/findings
paths=()
for p in data/paths/*.json; do paths+=(--path "$p"); done

# The per-triangle device profile the whole-frame and cpu-task-models pages
# compare with: data/policy.json of commit 5745e30 (needs a git clone).
per_triangle_policy() {
  git show 5745e30:data/policy.json > "$1" ||
    { echo "findings.sh: this step needs a git clone with commit 5745e30 (git show 5745e30:data/policy.json)" >&2; return 1; }
}

# ---- zpplus-cracks.md --------------------------------------------------------
step_bundled_scenes() {  # --method all on twelve bundled scenes, light 0; the table: five methods and the ray tracer
  for scene in default no_near_clip eye_in_shadow near_split case_d light_on_near_plane near_cap_bunny_wall \
               near_cap_bunny_cut twisted bunny armadillo far_grazing; do
    $n cracks "data/scenes/$scene.json" --light 0 --method all --out "$dir/$scene" > "$dir/$scene.json"
  done
  /usr/bin/python3 - "$dir" <<'EOF' > "$dir/table.md"
import json, sys
from pathlib import Path
d = Path(sys.argv[1])
cols = ["zpass", "zfail", "zpplus", "zpplus-corrected", "preload", "raytrace"]
print("| scene | seen | " + " | ".join(cols) + " |")
print("|---|---:|" + "---:|" * len(cols))
for f in sorted(d.glob("*.json")):
    rec = {r["method"]: r for r in json.loads(f.read_text())["methods"]}
    cells = [f"{rec[m]['wrong']:,} / {rec[m]['cracks']:,} / {rec[m]['count_mismatch']:,}" for m in cols if m in rec]
    print(f"| {f.stem} | {rec['zpass']['pixels_seen']:,} | " + " | ".join(cells) + " |")
EOF
}
step_stress() {  # the float methods on the stress test's 2,000 sampled hard configurations (those the reader accepts)
  NEARCAP_STRESS_SEED=2026 ./build/tests/nearcap_tests --gtest_filter='Stress.Float*'
}

# ---- far-plane.md ------------------------------------------------------------
step_far_plane_cap() {  # Z-fail's far modes and ZP+ corrected's switch
  for f in infinite clamp clamp-far far-cap; do
    local s=$f
    [ "$f" = infinite ] && s=clamp
    $n sweep --samples 3000 --seed 7 --methods zfail,zpplus-corrected --zfail-far "$f" --switch-clamp "$s" \
      --out "$dir/hard-$f.csv"
    $n sweep "${paths[@]}" --methods zfail,zpplus-corrected --zfail-far "$f" --switch-clamp "$s" --out "$dir/paths-$f.csv"
    $n report "$dir/hard-$f.csv" --out "$dir/report-hard-$f"
    $n report "$dir/paths-$f.csv" --out "$dir/report-paths-$f"
  done
}
step_infinite_far() {  # the infinite far plane's nudges
  local v=(--variant infinite-far=epsilon --variant infinite-far=doom3 --variant infinite-far=one-ulp)
  $n sweep --samples 3000 --seed 7 --methods zfail,preload,zpass --zpass-far infinite "${v[@]}" --out "$dir/hard.csv"
  $n sweep "${paths[@]}" --methods zfail,preload,zpass --zpass-far infinite "${v[@]}" --out "$dir/paths.csv"
  $n report "$dir/hard.csv" --out "$dir/report-hard"
  $n report "$dir/paths.csv" --out "$dir/report-paths"
}

# ---- l-near.md ---------------------------------------------------------------
step_l_near() {  # the l_near rules, then the fitted margin
  $n sweep --samples 300 --seed 5 --kinds light-near-plane,straddling,several-occluders,eye-in-shadow,tiny-near \
    --methods zpplus,zpplus-corrected,zfail --variant l-near=exact-max --variant l-near=near-clamp \
    --variant l-near=exact-max,l-near-scale=0.5 --variant l-near-scale=0.5 --out "$dir/rules.csv"
  $n report "$dir/rules.csv" --out "$dir/report"
  $n fit-l-near --samples 2000 --seed 3 --kinds light-near-plane,straddling,several-occluders,eye-in-shadow,tiny-near \
    --out "$dir/fit.json"
}

# ---- light-projection.md -----------------------------------------------------
step_light_projection() {  # P_l formulations and the clipped-sides cap on 1,000 hard cases
  $n sweep --samples 1000 --seed 9 --methods zpplus,zpplus-corrected,zfail --variant light-projection=glfrustum \
    --variant light-projection=composed --variant light-projection=rebased --out "$dir/formulations.csv"
  $n sweep --samples 1000 --seed 9 --methods zpplus,zpplus-corrected,zfail --variant light-projection=clipped-sides \
    --variant light-projection=clipped-sides,zpass-far=infinite --out "$dir/clipped-sides.csv"
  $n report "$dir/formulations.csv" --out "$dir/report-formulations"
  $n report "$dir/clipped-sides.csv" --out "$dir/report-clipped-sides"
}
step_clipped_sides_10k() {  # the clipped-sides cap on 10,000 other hard cases and the paths
  $n sweep --samples 10000 --seed 21 --methods zpplus,zfail \
    --variant light-projection=clipped-sides,zpass-far=infinite --out "$dir/hard.csv"
  $n sweep "${paths[@]}" --methods zpplus,zpplus-corrected,zfail \
    --variant light-projection=clipped-sides,zpass-far=infinite --out "$dir/paths.csv"
  $n report "$dir/hard.csv" --out "$dir/report-hard"
  $n report "$dir/paths.csv" --out "$dir/report-paths"
}

step_far_light() {  # the P_l formulations, the policy and the engines' rules under a far light, llvmpipe beside the model
  $n sweep --samples 1000 --seed 1 --kinds far-light --methods zpass,zfail,zpplus,zpplus-corrected,atomiczp \
    --variant light-projection=composed --variant light-projection=rebased \
    --variant light-projection=clipped-sides,zpass-far=infinite --out "$dir/far-light.csv"
  $n sweep --samples 1000 --seed 1 --kinds far-light --methods zfail --policies policy,doom3,doom3-bfg,ogre \
    --out "$dir/far-light-policies.csv"
  /usr/bin/python3 - "$dir/far-light.csv" "$dir/far-light-policies.csv" "$dir/worst.txt" <<'EOF' > "$dir/table.md"
import collections, csv, math, re, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["method"] != "rejected"]
rows += [r for r in csv.DictReader(open(sys.argv[2])) if r["method"] not in ("rejected", "zfail")]
zfail = {(r["configuration"], r["light"]): int(r["wrong"]) for r in rows
         if r["method"] == "zfail" and r["variant"] == "default"}
def decade(detail):  # "light 1eK away" or "light 2^K away": the distance's power of ten, rounded
    m = re.search(r"light (1e|2\^)(\d+) away", detail)
    return int(m.group(2)) if m.group(1) == "1e" else round(int(m.group(2)) * math.log10(2))
worse, pairs, wrong = collections.Counter(), collections.Counter(), collections.Counter()
for r in rows:
    key, d = (r["method"], r["variant"]), decade(r["detail"])
    pairs[key, d] += 1
    worse[key, d] += int(r["wrong"]) > zfail[r["configuration"], r["light"]]
    wrong[key] += int(r["wrong"])
decades = sorted({d for (_, d) in pairs})
print("| method | variant | wrong pixels | " + " | ".join(f"10^{d}" for d in decades) + " |")
print("|---|---|---:|" + "---:|" * len(decades))
for key in sorted({k for (k, _) in pairs}):
    cells = [f"{worse[key, d]} / {pairs[key, d]}" for d in decades]
    print(f"| {key[0]} | {key[1]} | {wrong[key]:,} | " + " | ".join(cells) + " |")
# The five configurations where published ZP+ is wrong on most pixels beyond Z-fail's.
excess = sorted(((int(r["wrong"]) - zfail[r["configuration"], r["light"]], r["configuration"].split(":")[2])
                 for r in rows if r["method"] == "zpplus" and r["variant"] == "default"), reverse=True)
open(sys.argv[3], "w").write("".join(f"{index}\n" for _, index in excess[:5]))
EOF
  while read -r index; do  # each drawn by llvmpipe beside the llvmpipe model
    $n sample --seed 1 --index "$index" --kinds far-light --out "$dir/far-light-$index.json"
    $n render "$dir/far-light-$index.json" --light 0 --method zpass,zfail,zpplus,zpplus-corrected,atomiczp --compare \
      --table --viewport llvmpipe --depth-interpolation llvmpipe --clipper mesa
  done < "$dir/worst.txt"
}

# ---- depth-precision.md ------------------------------------------------------
step_depth_precision() {  # reversed-Z, float depth and the tight near plane
  $n sweep --samples 300 --seed 5 --kinds tiny-near --methods all --variant depth=float32 \
    --variant depth-mapping=reversed --variant depth=float32,depth-mapping=reversed --variant near-plane=tight \
    --out "$dir/tiny-near.csv"
  $n sweep --samples 300 --seed 5 --kinds tiny-near --methods all --light-projection clipped-sides \
    --zpass-far infinite --variant depth=float32 --variant depth-mapping=reversed \
    --variant depth=float32,depth-mapping=reversed --variant near-plane=tight --out "$dir/tiny-near-clipped-sides.csv"
  $n sweep --samples 3000 --seed 7 --variant depth=float32,depth-mapping=reversed --variant near-plane=tight \
    --out "$dir/hard.csv"
  $n sweep --samples 300 --seed 5 --kinds tiny-near --methods zfail --policies policy --out "$dir/depth-limited.csv"
  for f in tiny-near tiny-near-clipped-sides hard depth-limited; do $n report "$dir/$f.csv" --out "$dir/report-$f"; done
}

# ---- raytrace.md -------------------------------------------------------------
step_raytrace_scenes() {  # the ray tracer's three epsilons on every bundled scene
  ./analysis/benchmarks/raytrace_table.sh; }
step_raytrace_hard_cases() {  # the ray tracer on 1,000 hard cases, per kind
  /usr/bin/python3 analysis/benchmarks/raytrace_hard_cases.py --samples 1000 --seed 1; }
step_raytrace_speed() {  # Embree against the exact reference, same scene and frame
  $bench/nearcap_raytrace_benchmarks; }

# ---- real-gl.md ----------------------------------------------------------------
step_gl_replay() {  # the real GL's stencil against the emulation's, every bundled scene
  ./analysis/benchmarks/gl_replay_table.sh; }
step_render_paths() {  # the real GL's frame times along the bundled paths
  ./analysis/benchmarks/render_paths_table.sh "$dir/work"; }
step_one_sided_stencil() {  # the stencil pass two-sided against one-sided, along each path
  for p in data/paths/*.json; do
    local name
    name=$(basename "$p" .json)
    for sided in two one; do
      local extra=()
      [ "$sided" = one ] && extra=(--one-sided-stencil)
      $n render --path "$p" --method zpass,zfail,zpplus-corrected,policy --bench --vertex-stage recorded "${extra[@]}" \
        --out "$dir/$name-$sided"
    done
  done
}
step_render_layouts() {  # the sides as triangles or as strips
  ./analysis/benchmarks/render_layout_table.sh "$dir/work"; }

# ---- volume-culling.md ---------------------------------------------------------
step_volume_culling() {  # fragments with each culling, then the stencil pass on llvmpipe
  for c in none scissor depth-bounds both; do
    $n sweep "${paths[@]}" --methods all --policies policy --volume-culling "$c" --out "$dir/paths-$c.csv"
    $n sweep --samples 3000 --seed 7 --methods all --policies policy --volume-culling "$c" --out "$dir/hard-$c.csv"
  done
  python3 analysis/benchmarks/volume_culling_fragments.py "$dir"
  ./analysis/benchmarks/render_culling_table.sh "$dir/work"
}

# ---- engine-baselines.md -------------------------------------------------------
step_engine_baselines() {  # the engines' per-occluder rules on 2,000 hard cases
  $n sweep --samples 2000 --seed 4 --methods zpass,zfail --policies all --out "$dir/base.csv"
  $n report "$dir/base.csv" --out "$dir/report"
}

# ---- policy.md -----------------------------------------------------------------
step_policy_tuning() {  # the shipped policies, tuned again (into out/findings/, not over data/)
  ./analysis/tuning/tune_policy.sh build "$dir/policy.json"
  ./analysis/tuning/tune_policy.sh --tight-near build "$dir/policy-tight-near.json"
  ./analysis/tuning/tune_policy.sh --reversed-z build "$dir/policy-reversed-z.json"
}
step_policy_oracle() {  # the shipped policy against the oracle and the fixed rules, end to end on the real GL
  $n evaluate --policy data/policy.json --samples 500 --seed 4242 --width 160 --height 120 \
    --path data/paths/near_plane_sweep.json --path data/paths/fly_around.json --repeats 8 --out "$dir/policy-oracle"
}
step_price_residuals() {  # how far a work-based price follows a whole frame's GL time (docs/findings/policy-oracle.md)
  $n calibrate --samples 500 --seed 4242 --width 160 --height 120 --out "$dir/cal-4242.csv"
  $n calibrate --samples 500 --seed 4242 --width 160 --height 120 --out "$dir/cal-4242-again.csv"
  python3 analysis/benchmarks/frame_price_residuals.py "$dir/cal-4242.csv" data/policy.json "$dir/cal-4242-again.csv"
}
step_prediction_floor() {  # the policy's predicted frame time against the same frames timed in other runs
  local k
  for k in first again third; do
    $n evaluate --policy data/policy.json --samples 500 --seed 4242 --width 160 --height 120 \
      --path data/paths/near_plane_sweep.json --path data/paths/fly_around.json --repeats 8 --out "$dir/prediction-floor-$k"
  done
  python3 analysis/benchmarks/prediction_floor.py "$dir/prediction-floor-first/evaluation.csv" \
    "$dir/prediction-floor-again/evaluation.csv" "$dir/prediction-floor-third/evaluation.csv"
}
step_released_workers() {  # the policy-oracle command with oneTBB's workers released before timing, against a build of dd2b93a (not released), alternated
  local old=$dir/nearcap-dd2b93a k build name
  git worktree prune
  git worktree add --detach "$old" dd2b93a
  cmake -S "$old" -B "$old/build" -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
  ninja -C "$old/build" nearcap > /dev/null
  for k in 1 2 3; do
    for build in $( ((k % 2)) && echo "build $old/build" || echo "$old/build build"); do
      name=$([ "$build" = build ] && echo released || echo spinning)-$k
      echo "== $name, $(date -u +%H:%M:%S) UTC"
      "$build/nearcap" evaluate --policy data/policy.json --samples 500 --seed 4242 --width 160 --height 120 \
        --path data/paths/near_plane_sweep.json --path data/paths/fly_around.json --repeats 8 --out "$dir/$name" > /dev/null
      grep -E '^### |^\| (oracle|policy|always-zfail|always-clipped|exact-zpass\+zfail|doom3|doom3-bfg) |noise floor|predicted frame time' "$dir/$name/table.md"
    done
  done
  for name in released spinning; do
    echo "== prediction_floor.py, $name"
    python3 analysis/benchmarks/prediction_floor.py "$dir/$name-1/evaluation.csv" "$dir/$name-2/evaluation.csv" \
      "$dir/$name-3/evaluation.csv"
  done
  git worktree remove --force "$old"
}
step_recalibrated_profile() {  # the policy-oracle command with data/policy.json against the profile of 057fc4e (calibrated with the workers spinning), alternated
  local k name policy
  git show 057fc4e:data/policy.json > "$dir/policy-057fc4e.json"
  for k in 1 2 3; do
    for name in $( ((k % 2)) && echo "recalibrated 057fc4e" || echo "057fc4e recalibrated"); do
      policy=$([ "$name" = recalibrated ] && echo data/policy.json || echo "$dir/policy-057fc4e.json")
      echo "== $name-$k, $(date -u +%H:%M:%S) UTC"
      $n evaluate --policy "$policy" --samples 500 --seed 4242 --width 160 --height 120 \
        --path data/paths/near_plane_sweep.json --path data/paths/fly_around.json --repeats 8 --out "$dir/$name-$k" > /dev/null
      grep -E '^### |^\| (oracle|policy|always-zfail|always-clipped|exact-zpass\+zfail|exact-zpass\+clipped|doom3|doom3-bfg) |decision:|noise floor|predicted frame time|frames 40-59' "$dir/$name-$k/table.md"
    done
  done
  for name in recalibrated 057fc4e; do
    echo "== prediction_floor.py, $name"
    python3 analysis/benchmarks/prediction_floor.py "$dir/$name-1/evaluation.csv" "$dir/$name-2/evaluation.csv" \
      "$dir/$name-3/evaluation.csv"
  done
}
step_decision_instructions() {  # the decision's instructions on near_plane_sweep (callgrind, one core)
  ./analysis/benchmarks/decision_instructions.sh build data/paths/near_plane_sweep.json; }
step_whole_frame() {  # a whole frame against its passes timed each on its own; the frame row's effect end to end
  local calibration=() p
  for p in data/paths/*.json; do
    case $(basename "$p" .json) in near_plane_sweep | fly_around) ;; *) calibration+=(--path "$p") ;; esac
  done
  $n calibrate --samples 100 --seed 100 "${calibration[@]}" --width 160 --height 120 \
    --out "$dir/whole-frame.csv" --policy data/policy.json --write-policy "$dir/policy-frame-row.json"
  python3 analysis/benchmarks/frame_against_passes.py "$dir/whole-frame.csv"
  python3 -c 'import json,sys; p=json.load(open(sys.argv[1])); del p["device_profile"]["frame"]; json.dump(p,open(sys.argv[2],"w"),indent=1)' \
    "$dir/policy-frame-row.json" "$dir/policy-no-frame-row.json"
  per_triangle_policy "$dir/policy-5745e30.json"
  for p in policy-frame-row policy-no-frame-row policy-5745e30; do
    $n evaluate --policy "$dir/$p.json" --samples 500 --seed 4242 --width 160 --height 120 \
      --path data/paths/near_plane_sweep.json --path data/paths/fly_around.json --repeats 8 --out "$dir/$p"
  done
}
step_in_view_triangles() {  # what a pass's triangles in view add to its cost model (docs/findings/in-view-triangles.md)
  $n calibrate --samples 0 --path near_plane_sweep --width 160 --height 120 --out "$dir/in-view-sweep.csv"
  python3 -c 'import csv,sys
  print("frame  triangles  in view  fragments  ms")
  for r in csv.DictReader(open(sys.argv[1])):
      if r["record"] == "pass" and r["kind"] == "depth" and r["frame"].endswith(":zfail") and int(r["frame"].split(":")[2]) % 8 == 0:
          print(r["frame"].split(":")[2], r["triangles"], r["in_view"], r["fragments"], r["ms"])' "$dir/in-view-sweep.csv"
  local calibration=() p
  for p in data/paths/*.json; do
    case $(basename "$p" .json) in near_plane_sweep | fly_around) ;; *) calibration+=(--path "$p") ;; esac
  done
  $n calibrate --samples 100 --seed 100 "${calibration[@]}" --width 160 --height 120 \
    --out "$dir/in-view.csv" --policy data/policy.json --write-policy "$dir/policy-in-view.json" --no-atomiczp
  python3 analysis/benchmarks/in_view_fit.py "$dir/in-view.csv"
}
step_cpu_task_models() {  # a profile fitted by counts against the per-triangle one, in one window, end to end
  local calibration=()
  for p in data/paths/*.json; do
    case $(basename "$p" .json) in near_plane_sweep | fly_around) ;; *) calibration+=(--path "$p") ;; esac
  done
  $n calibrate --samples 100 --seed 100 "${calibration[@]}" --width 160 --height 120 \
    --out "$dir/calibration.csv" --policy data/policy.json --write-policy "$dir/policy-counts.json"
  # the per-triangle profile the page compares with
  per_triangle_policy "$dir/policy-per-triangle.json"
  local round policy
  for round in 1 2; do
    for policy in "$dir/policy-per-triangle.json" "$dir/policy-counts.json"; do
      $n evaluate --policy "$policy" --samples 0 --width 160 --height 120 \
        --path data/paths/near_plane_sweep.json --repeats 8 --out "$dir/$(basename "$policy" .json)-$round"
    done
  done
}
step_policy_evaluation() {  # the policies and the engines' rules on configurations not tuned on
  $n sweep --samples 3000 --seed 7 --policies all --out "$dir/ev.csv"
  $n sweep "${paths[@]}" --policies all --out "$dir/ev-paths.csv"
  for pol in data/policy-tight-near.json data/policy-reversed-z.json; do
    local name
    name=$(basename "$pol" .json)
    $n sweep --samples 3000 --seed 7 --methods zfail --policies policy --policy "$pol" --out "$dir/ev-$name.csv"
    $n sweep "${paths[@]}" --methods zfail --policies policy --policy "$pol" --out "$dir/ev-paths-$name.csv"
  done
  $n report "$dir/ev.csv" --out "$dir/report" --policy data/policy.json
  $n report "$dir/ev-paths.csv" --out "$dir/report-paths" --policy data/policy.json
  $bench/nearcap_benchmarks --benchmark_filter=PolicyCost
}

# ---- sweep-speed.md, exact-speed.md --------------------------------------------
step_sweep_rates() {  # configurations per second
  ./analysis/benchmarks/sweep_rates.sh; }
step_orbit_instructions() {  # the bunny orbit's instructions per frame (callgrind, one core)
  ./analysis/benchmarks/orbit_instructions.sh; }
step_orbit_against_168e363() {  # the orbit's rate against a build of 168e363, alternated (the code its target was set on)
  local old=$dir/nearcap-168e363
  git worktree prune
  git worktree add --detach "$old" 168e363
  cmake -S "$old" -B "$old/build" -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
  ninja -C "$old/build" nearcap > /dev/null
  ./analysis/benchmarks/orbit_against_build.sh build "$old/build" 8
  ./analysis/benchmarks/orbit_against_build.sh build "$old/build" 8 --methods zpass,zfail,zpplus,zpplus-corrected,preload
  ./analysis/benchmarks/orbit_against_build.sh build build 4
  ./analysis/benchmarks/orbit_against_build.sh "$old/build" "$old/build" 4
  for build in "$old/build" build build "$old/build"; do
    echo "sweep_rates.sh $build"
    ./analysis/benchmarks/sweep_rates.sh "$build"
  done
  git worktree remove --force "$old"
}
step_shadow_method_speed() {  # the emulated frame on the armadillo: each method but AtomicZP, then all six back to back
  $bench/nearcap_benchmarks --benchmark_filter='ShadowMethod|AllShadow'; }
step_classification_speed() {  # exact against float classification on the bunny
  $bench/nearcap_benchmarks --benchmark_filter=Classification --benchmark_repetitions=3 \
    --benchmark_report_aggregates_only=true
}
step_reference_speed() {  # the per-pixel reference: the benchmark, then two scenes
  $bench/nearcap_benchmarks --benchmark_filter=PixelReference
  for scene in default armadillo; do
    $n reference "data/scenes/$scene.json" --light 0 --out "$dir/$scene"
  done
}
step_reference_setup() {  # the reference's setup on 1 and 2 threads, its serial fraction; then with freed memory kept
  local run
  for run in 1 2; do $bench/nearcap_benchmarks --benchmark_filter=ReferenceSetup; done
  local keep=glibc.malloc.trim_threshold=1073741824:glibc.malloc.mmap_threshold=1073741824
  for run in 1 2; do GLIBC_TUNABLES=$keep $bench/nearcap_benchmarks --benchmark_filter=ReferenceSetup; done
}
step_cap_arrangement() {  # the exact near-cap's build time ("ms") and faces, three runs each
  for scene in near_cap_bunny_silhouettes near_split case_d bunny armadillo; do
    for run in 1 2 3; do
      $n cap "data/scenes/$scene.json" --light 0 --out "$dir/$scene-$run.json"
    done
  done
}
step_memory() {  # peak resident memory at 2048 x 2048 (a box over the ground), and per configuration kept
  local m=$PWD/data/meshes
  cat > "$dir/scene.json" <<EOF
{"camera":{"eye":[0,2.5,5],"target":[0,0.7,0],"up":[0,1,0],"fovy_deg":50,"near":0.1,"far":100,
 "width":2048,"height":2048},"lights":[{"position":[2,5,1.5]}],
 "objects":[{"mesh":"$m/box.off","translate":[0,1,0]},{"mesh":"$m/ground.off","occluder":false}]}
EOF
  /usr/bin/time -f "reference: %M KB" $n reference "$dir/scene.json" --light 0 --out "$dir/out" >/dev/null
  for methods in zpass zpass,zfail all; do
    /usr/bin/time -f "cracks --method $methods: %M KB" $n cracks "$dir/scene.json" --light 0 --method "$methods" \
      --out "$dir/out" >/dev/null
  done
  for s in 1024 2048; do  # the commands that draw sampled configurations at --width x --height
    /usr/bin/time -f "calibrate --samples 6 at $s: %M KB" $n calibrate --samples 6 --width $s --height $s \
      --out "$dir/c$s.csv" >/dev/null 2>"$dir/calibrate.err" || cat "$dir/calibrate.err"
    tail -1 "$dir/calibrate.err"
    /usr/bin/time -f "evaluate --samples 3 at $s: %M KB" $n evaluate --samples 3 --width $s --height $s \
      --out "$dir/e$s" >/dev/null 2>"$dir/evaluate.err" || cat "$dir/evaluate.err"
    tail -1 "$dir/evaluate.err"
  done
  # What each configuration keeps to the end: the peak at two counts (default sizes)
  for c in 40 1280; do
    /usr/bin/time -f "calibrate --samples $c: %M KB" $n calibrate --samples $c --seed 100 --out "$dir/k$c.csv" \
      >/dev/null 2>"$dir/calibrate.err" || cat "$dir/calibrate.err"
    tail -1 "$dir/calibrate.err"
  done
  for c in 40 320; do
    /usr/bin/time -f "evaluate --samples $c: %M KB" $n evaluate --samples $c --seed 4242 --out "$dir/v$c" \
      >/dev/null 2>"$dir/evaluate.err" || cat "$dir/evaluate.err"
    tail -1 "$dir/evaluate.err"
  done
}

# ---- cap-cpu-time.md -------------------------------------------------------------
step_cap_cpu_time() {  # the clipped-sides cap's construction time per frame, three runs each
  for r in 1 2 3; do
    for p in near_plane_sweep fly_around; do
      $n render --path data/paths/$p.json --method zpass,zfail,zpplus-corrected,policy \
        --light-projection clipped-sides --bench --out "$dir/$p-$r"
    done
    python3 analysis/benchmarks/cap_cpu_table.py "$dir/near_plane_sweep-$r/render.json" near_plane_sweep 40 59
    python3 analysis/benchmarks/cap_cpu_table.py "$dir/fly_around-$r/render.json" fly_around
  done
}

# ---- report-scale.md -------------------------------------------------------------
step_report_scale() {  # nearcap report's time and peak memory on 1M and 5.8M rows
  $n sweep --samples 40 --policies all --out "$dir/s.csv"
  python3 analysis/report/replicate_rows.py "$dir/s.csv" 1000000 "$dir/big1m.csv"
  python3 analysis/report/replicate_rows.py "$dir/s.csv" 5800000 "$dir/big5m8.csv"
  /usr/bin/time -v $n report "$dir/big1m.csv" --out "$dir/n1m"
  /usr/bin/time -v $n report "$dir/big5m8.csv" --out "$dir/r5m8"
}

# ---- fuzzing.md ------------------------------------------------------------------
step_fuzz_campaign() {  # 10 million executions per fuzz target
  NEARCAP_FUZZ_RUNS=10000000 ./scripts/fuzz.sh 0; }

steps=(bundled-scenes stress far-plane-cap infinite-far l-near light-projection clipped-sides-10k far-light depth-precision
       raytrace-scenes raytrace-hard-cases raytrace-speed gl-replay render-paths one-sided-stencil render-layouts
       volume-culling engine-baselines policy-tuning policy-evaluation policy-oracle price-residuals prediction-floor released-workers recalibrated-profile decision-instructions whole-frame cpu-task-models in-view-triangles sweep-rates orbit-instructions orbit-against-168e363 shadow-method-speed
       classification-speed reference-speed reference-setup cap-arrangement memory cap-cpu-time report-scale fuzz-campaign)

if [ "${1:-}" = "--list" ]; then
  for s in "${steps[@]}"; do
    printf '%-22s %s\n' "$s" "$(grep -A1 "^step_${s//-/_}()" "$0" | head -1 | sed -n 's/.*# //p')"
  done
  exit 0
fi
chosen=("$@")
[ ${#chosen[@]} -eq 0 ] && chosen=("${steps[@]}")
for s in "${chosen[@]}"; do
  if ! declare -F "step_${s//-/_}" >/dev/null; then
    echo "findings: no step '$s' (./scripts/findings.sh --list)" >&2
    exit 2
  fi
done
for s in "${chosen[@]}"; do
  dir=$top/$s
  rm -rf "$dir"
  mkdir -p "$dir"
  echo "== findings: $s ($(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores) -> $dir/log.txt"
  "step_${s//-/_}" > "$dir/log.txt" 2>&1 || { echo "findings: step $s failed; see $dir/log.txt" >&2; exit 1; }
done
