#!/usr/bin/env bash
# Create .venv and install symlearn with everything it needs, on a fresh Debian machine or an
# already prepared one. Idempotent: a stamp records the hash of pyproject.toml and the extras,
# so a second run only checks and returns.
#
#   scripts/bootstrap.sh               runtime dependencies (graphviz)
#   scripts/bootstrap.sh --with-tests  plus test tools, peer/oracle packages, SUMO and Debian mona
set -euo pipefail
cd "$(dirname "$0")/.."

with_tests=0
[[ "${1:-}" == "--with-tests" ]] && with_tests=1

say() { printf 'bootstrap: %s\n' "$*" >&2; }

# --- Debian packages -------------------------------------------------------------------
apt_needed=()
command -v dot  >/dev/null 2>&1 || apt_needed+=(graphviz)
if (( with_tests )); then command -v mona >/dev/null 2>&1 || apt_needed+=(mona); fi
if (( ${#apt_needed[@]} )); then
    sudo=""
    if [[ $(id -u) -ne 0 ]]; then
        if command -v sudo >/dev/null 2>&1; then sudo="sudo"; else
            say "need Debian packages ${apt_needed[*]} but am not root and have no sudo; install them and rerun"
            exit 1
        fi
    fi
    say "installing Debian packages: ${apt_needed[*]}"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${apt_needed[@]}" >/dev/null
fi

# --- Python environment ------------------------------------------------------------------
pick_python() {
    for candidate in "${PYTHON:-}" python3.13 python3.12 python3.11 python3; do
        [[ -n "$candidate" ]] || continue
        if command -v "$candidate" >/dev/null 2>&1 &&
           "$candidate" -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else 1)' 2>/dev/null; then
            echo "$candidate"; return 0
        fi
    done
    return 1
}
# torch==2.13.0 is a CPU wheel for CPython 3.11 on our machines, so prefer 3.11 when present.
if command -v python3.11 >/dev/null 2>&1; then py=python3.11; else py=$(pick_python) || {
    say "Python >= 3.11 is required"; exit 1; }; fi

if [[ ! -x .venv/bin/python ]]; then
    say "creating .venv with $($py --version)"
    "$py" -m venv .venv
fi

extras="peers"
(( with_tests )) && extras="peers,test,sumo,sb3,highway,sweep,mujoco"
stamp=".venv/.symlearn-installed"
# An editable install compiles nothing ahead, and machines that set PYTHONDONTWRITEBYTECODE never
# keep what the interpreter compiles, so every command would compile the modules it imports again
# (measured: `symlearn ltl parse` 0.11 s -> 0.04 s wall with them compiled). compileall writes the
# bytecode files regardless of that variable and only recompiles sources newer than their file, so
# it runs on every call: after a `git pull` the changed modules are compiled once more.
compile_package() { .venv/bin/python -m compileall -q -j 0 symlearn >/dev/null || say "could not compile symlearn's bytecode (it still runs, each command compiling what it imports)"; }
want="$(sha256sum pyproject.toml | cut -d' ' -f1) $extras"
have="$(cat "$stamp" 2>/dev/null || true)"
# A test install also satisfies a plain one.
if [[ "$have" == "$want" ]] || { (( ! with_tests )) && [[ "$have" == "$(sha256sum pyproject.toml | cut -d' ' -f1) peers,test,sumo,sb3,highway,sweep,mujoco" ]]; }; then
    compile_package
    exit 0
fi
say "installing symlearn[$extras] into .venv (first run takes a few minutes)"
# pip's own chatter goes to a log that is shown only when an install fails.
log=.venv/pip-install.log
pip_install() {
    if ! .venv/bin/python -m pip install --disable-pip-version-check "$@" >>"$log" 2>&1; then
        tail -n 40 "$log" >&2
        say "pip install $* failed (full log: $log)"
        exit 1
    fi
}
: > "$log"
pip_install --upgrade pip
# torch first and pinned, so no other requirement can pull a CUDA build.
pip_install "torch==2.13.0"
pip_install -e ".[$extras]"
compile_package
echo "$want" > "$stamp"
say "ready"
