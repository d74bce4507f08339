#!/usr/bin/env bash
# Regenerates every figure in docs/figures with the commands the guides give for them
# (docs/reproduction.md, docs/global.md, docs/stability.md, docs/accuracy.md), then copies the
# pictures here under their names in the guides.
#
#   docs/figures/regenerate.sh            # everything (about 15 minutes on 2 loaded cores)
#   docs/figures/regenerate.sh poincare   # only some groups: bifurcation poincare ring_phase
#                                         # basins param_map continuation stability work_precision
#
# The runs write into target/figures/regenerate (removed first, so that the resumable sweeps of
# basins and param_map start over; REUSE=1 keeps it, and an interrupted sweep resumes). NICE=0
# runs without `nice`; BUILD=0 uses the example binaries already built; DEST=DIR copies the
# pictures there instead of docs/figures (CI: .ci/commands); PROFILE=test builds and runs the
# examples in Cargo's test profile (target/debug: in CI, the builds `cargo test` made) instead of
# release. Run from anywhere inside the repository.
set -euo pipefail

cd "$(git rev-parse --show-toplevel)"
out=target/figures/regenerate
dest=${DEST:-docs/figures}
profile=${PROFILE:-release}
case $profile in
release) bin=target/release/examples ;;
dev | test) bin=target/debug/examples ;;
*) bin=target/$profile/examples ;;
esac
nice_cmd=(nice)
[[ "${NICE:-1}" == 0 ]] && nice_cmd=()
[[ "${REUSE:-0}" == 1 ]] || rm -rf "$out"
mkdir -p "$out" "$dest"

all=(bifurcation poincare ring_phase basins param_map continuation stability work_precision)
groups=("$@")
[[ ${#groups[@]} -eq 0 ]] && groups=("${all[@]}")
for g in "${groups[@]}"; do
    [[ " ${all[*]} " == *" $g "* ]] || { echo "unknown group: $g (one of: ${all[*]})" >&2; exit 2; }
done

[[ "${BUILD:-1}" == 0 ]] || "${nice_cmd[@]}" cargo build --profile "$profile" --examples

# `run NAME ARGS...`: runs an example, timed, its output in $out/NAME.log.
run() {
    local name=$1
    shift
    local t0=$SECONDS
    echo "== $name $*" >&2
    "${nice_cmd[@]}" "$bin/$name" "$@" > >(tee -a "$out/$name.log") 2> >(tee -a "$out/$name.log" >&2)
    echo "== $name: $((SECONDS - t0)) s" >&2
}
# `copy FROM TO`: a picture from $out to docs/figures.
copy() { cp "$out/$1" "$dest/$2"; }

start=$SECONDS
for g in "${groups[@]}"; do
    case $g in
    bifurcation) # docs/reproduction.md, Fig. 8: every η from rest, then the state carried over
        run bifurcation --out "$out/bifurcation"
        copy bifurcation/fig8a.png fig8a.png
        copy bifurcation/fig8b.png fig8b.png
        run bifurcation --mode carry --chunks 1 --out "$out/bifurcation_carry"
        copy bifurcation_carry/fig8a.png fig8a_carry.png
        copy bifurcation_carry/fig8b.png fig8b_carry.png
        ;;
    poincare) # docs/reproduction.md, Fig. 9: (a) and (b) at the captions' η and swapped
        run poincare --out "$out/poincare"
        for f in fig9a fig9a_eta2.181 fig9b fig9b_eta2.223 fig9c fig9d; do
            copy "poincare/$f.png" "$f.png"
        done
        ;;
    ring_phase) # docs/reproduction.md, Fig. 10
        run ring_phase --out "$out/ring_phase"
        for p in a b c d; do copy "ring_phase/fig10$p.png" "fig10$p.png"; done
        ;;
    basins) # docs/global.md, basins of attraction
        run basins --out "$out/basins"
        copy basins/fig8a-eta2.2/basins.png global_basins_fig8a.png
        copy basins/fig8b-eta2.2/basins.png global_basins_fig8b.png
        copy basins/fig10a-eta2.5/basins.png global_basins_fig10a.png
        ;;
    param_map) # docs/global.md, two-parameter maps
        run param_map --out "$out/param_map"
        for m in preload ecc; do
            copy "param_map/$m/period.png" "global_map_${m}_period.png"
            copy "param_map/$m/contacts.png" "global_map_${m}_contacts.png"
        done
        ;;
    continuation) # docs/global.md, the branch with its flip and switch; the coexistence diagrams
        run continuation --param eta --from 2 --to 2.45 --period 1 --switch \
            --out "$out/continuation"
        copy continuation/branch.png global_branch_period1_fig8a.png
        run continuation --coexistence --out "$out/continuation"
        copy continuation/coexistence_fig8a.png global_coexistence_fig8a.png
        copy continuation/coexistence_fig8b.png global_coexistence_fig8b.png
        ;;
    stability) # docs/stability.md, section 4
        run stability pictures --values 301 --periods 1000 --step 0.002 --out "$out/stability"
        for f in multipliers_period1 lyapunov_fig8a lyapunov_fig8b; do
            copy "stability/$f.png" "stability_$f.png"
        done
        ;;
    work_precision) # docs/accuracy.md
        run work_precision --out "$out/work_precision" --repeat 7
        for s in fig8a fig8b stiff chaos; do
            copy "work_precision/wp_${s}_rhs.png" "wp_${s}_rhs.png"
            copy "work_precision/wp_${s}_time.png" "wp_${s}_time.png"
        done
        ;;
    esac
done
echo "regenerated ${groups[*]} in $((SECONDS - start)) s; logs in $out/*.log" >&2
