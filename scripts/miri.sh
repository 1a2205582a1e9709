#!/usr/bin/env bash
# The engine's unit tests under Miri, which stops at any undefined behaviour: the
# `unsafe` code (SIMD intrinsics, gathers and scatters through pointers, the runs and
# velocities the solver's threads share, the `set_len`s) run in an interpreter that
# checks every access, and the threaded paths checked for data races. Three runs: SSE
# (every x86-64), then with AVX and with AVX-512 turned on, so each SIMD path is taken;
# and, with MIRI_PLAIN=1, a fourth of the lanes' plain-array path (wasm32 and every
# other processor).
# The library is built without its `window` feature: the engine alone, quick to build.
# Installs nightly's Miri when it is missing; when it cannot (no network), says so on
# one line and exits 0. Usage: bash scripts/miri.sh
set -euo pipefail
cd "$(dirname "$0")/.."

# Nightly with Miri and the standard library's sources, added only where missing (no
# update of a nightly already there).
if ! command -v rustup >/dev/null; then
    echo "miri: skipped: no rustup here to install the nightly toolchain Miri needs"
    exit 0
fi
installed="$(rustup component list --toolchain nightly --installed 2>/dev/null || true)"
if ! grep -q '^miri' <<<"$installed" || ! grep -q '^rust-src' <<<"$installed"; then
    echo "installing: nightly toolchain with miri and rust-src"
    if [ -z "$installed" ]; then
        install=(rustup toolchain install nightly --profile minimal --component miri,rust-src)
    else
        install=(rustup component add --toolchain nightly miri rust-src)
    fi
    if ! "${install[@]}" >/dev/null 2>&1; then
        echo "miri: skipped: the nightly toolchain with Miri could not be installed (no network?)"
        exit 0
    fi
fi
# Miri's own build of the standard library (once; it fetches std's crates).
if ! cargo +nightly miri setup >/dev/null 2>&1; then
    echo "miri: skipped: Miri could not build its standard library (no network?)"
    exit 0
fi

# The engine's tests (`physics::`); those too slow to interpret that hold no unsafe code
# are marked `#[cfg_attr(miri, ignore = ...)]`. The library is built once; the target
# features reach only the interpreted crate (MIRIFLAGS), so the three runs share it.
miri_test=(cargo +nightly miri test --lib --no-default-features)
"${miri_test[@]}" --no-run
# The tests on one thread run under Miri's default aliasing rules, Stacked Borrows. The
# rest start rayon's threads, whose crossbeam-epoch breaks those rules (a known issue,
# crossbeam-rs/crossbeam#545, not this crate's): they run under Tree Borrows, which
# crossbeam passes, with its integer-to-pointer casts allowed quietly, and leaks
# allowed (rayon's pools never join their threads). With AVX and AVX-512 only the tests
# whose path depends on them run again: the SIMD ones, and a pile stepped on threads.
alone=(
    physics::wide physics::solver::soft::contact physics::particles::turning
    physics::solver::soft::shared::tests::shared_velocities
    physics::collision::broad_phase::tests::keeping_without_a_branch
)
not_alone=(physics::)
for test in "${alone[@]}"; do not_alone+=(--skip "$test"); done
for features in "" "+avx" "+avx,+avx512f,+avx512vl"; do
    echo "miri: the engine's unit tests, target features: ${features:-x86-64 baseline (SSE2)}"
    flags=(-Zmiri-ignore-leaks)
    skip=()
    if [ -n "$features" ]; then
        flags+=("-Ctarget-feature=$features")
        not_alone=(physics::world::tests::a_small_pile_steps_alike_on_one_and_two_threads)
    fi
    if [[ "$features" == *avx512f* ]]; then
        # Miri has no AVX-512 compare or max (`_mm512_cmp_ps_mask`, `_mm512_max_ps`):
        # the tests that reach them run everywhere but here.
        skip=(--skip physics::wide::tests::sixteen_lanes_equal_two_eights
            --skip physics::solver::soft::contact::tests::a_contact_that_stays_without_impulse)
    fi
    MIRIFLAGS="${MIRIFLAGS:-} ${flags[*]}" "${miri_test[@]}" -q -- "${alone[@]}" "${skip[@]}"
    MIRIFLAGS="${MIRIFLAGS:-} ${flags[*]} -Zmiri-tree-borrows -Zmiri-permissive-provenance" \
        "${miri_test[@]}" -q -- "${not_alone[@]}"
done

# The plain arrays that stand in for SSE off x86-64 (the browser's wasm32): the tests
# of the lanes, their gathers and scatters and the contact solve, interpreted for
# 64-bit ARM. criterion's `alloca` (a dev-dependency) compiles C in its build script,
# which Miri never runs or links: the host's compiler stands in for a cross compiler.
# It builds a second standard library and every crate again for aarch64 (about five
# minutes more, cold), so the test command leaves it out; MIRI_PLAIN=1 runs it.
if [ "${MIRI_PLAIN:-0}" != 1 ]; then
    echo "miri: the lanes' plain-array path not interpreted this run (MIRI_PLAIN=1 bash scripts/miri.sh runs it)"
    exit 0
fi
echo "miri: the lanes' plain-array path (aarch64: no SSE)"
arm=(--target aarch64-unknown-linux-gnu)
export CC_aarch64_unknown_linux_gnu="${CC_aarch64_unknown_linux_gnu:-cc}"
export AR_aarch64_unknown_linux_gnu="${AR_aarch64_unknown_linux_gnu:-ar}"
if ! command -v "$CC_aarch64_unknown_linux_gnu" >/dev/null; then
    echo "miri: skipped the plain-array path: no C compiler ($CC_aarch64_unknown_linux_gnu) for the build scripts"
    exit 0
fi
if ! cargo +nightly miri setup "${arm[@]}" >/dev/null 2>&1; then
    echo "miri: skipped the plain-array path: Miri could not build its aarch64 standard library (no network?)"
    exit 0
fi
MIRIFLAGS="${MIRIFLAGS:-} -Zmiri-ignore-leaks" "${miri_test[@]}" "${arm[@]}" -q -- \
    physics::wide physics::solver::soft::contact physics::solver::soft::shared::tests::shared_velocities
