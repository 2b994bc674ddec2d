#!/usr/bin/env bash
# The Linux wheel installs and runs where there is no C compiler (issue 26; docs/platforms.md):
# build and repair it (tools/build_wheel.sh), check its tags (cp311-abi3, manylinux), install it
# into a fresh venv with CC=/bin/false and a PATH without gcc, and run `uplift --version` and a
# short exact analysis of the bundled deck from outside the source tree, checking that the
# compiled loops of the installed wheel run (not the numpy twins, not the source tree's); then
# the README's first command, after its install, in an empty folder: the wheel alone writes the
# examples (`uplift examples`, the repository's inputs/ and records/ byte for byte) and runs one.
#
#   tools/check_wheel.sh [WHEEL]        (default: build one with tools/build_wheel.sh)
#
# PYTHON (default .venv/bin/python, else python3) provides pip: the dependencies come from its
# cache (warm after the project's own install: no download, ~20 s on 2 cores), binary only.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
python="${PYTHON:-$root/.venv/bin/python}"
[ -x "$python" ] || python="$(command -v python3)"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
fail() { echo "check_wheel.sh: $*" >&2; exit 1; }

wheel="${1:-$(PYTHON="$python" "$root/tools/build_wheel.sh" "$scratch/dist" | tail -n 1)}"
case "$(basename "$wheel")" in
    upliftcli-*-cp311-abi3-manylinux*_"$(uname -m)".whl) ;;
    *) fail "$wheel is not a cp311-abi3 manylinux wheel for $(uname -m)" ;;
esac

# a fresh venv without pip of its own (the outer pip installs into it: no ensurepip, 3 s less)
"$python" -m venv --without-pip "$scratch/venv"
mkdir "$scratch/bin" "$scratch/work"
ln -s "$scratch/venv/bin/python" "$scratch/bin/python"
no_compiler=(env -i HOME="$scratch" PATH="$scratch/venv/bin:$scratch/bin" CC=/bin/false CXX=/bin/false
             LANG=C.UTF-8 MPLBACKEND=Agg)
"${no_compiler[@]}" /bin/sh -c 'for c in gcc cc clang; do command -v $c && exit 0; done; exit 1' >/dev/null 2>&1 && fail "a C compiler is on the check's PATH"
# binary only: pip may not build anything (nothing could be, without a compiler)
PIP_CACHE_DIR="$("$python" -m pip cache dir)" CC=/bin/false CXX=/bin/false \
    "$python" -m pip --python "$scratch/venv/bin/python" install -q --only-binary=:all: "$wheel"

# cibuildwheel's test of the wheel ([tool.cibuildwheel] in pyproject.toml), as it runs it: its
# test-requires installed, its test-sources copied, its test-command run with its test-environment
"$python" - "$root/pyproject.toml" "$scratch" <<'PY'
import shlex, sys, tomllib
config = tomllib.load(open(sys.argv[1], "rb"))["tool"]["cibuildwheel"]
with open(f"{sys.argv[2]}/cibuildwheel.sh", "w") as script:
    script.write(f"sources=({' '.join(map(shlex.quote, config['test-sources']))})\n")
    script.write(f"requires=({' '.join(map(shlex.quote, config['test-requires']))})\n")
    environment = " ".join(f"{name}={shlex.quote(value)}" for name, value in config["test-environment"].items())
    script.write(f"environment=({environment})\n")
    script.write(f"command={shlex.quote(' && '.join(config['test-command']))}\n")
PY
source "$scratch/cibuildwheel.sh"
PIP_CACHE_DIR="$("$python" -m pip cache dir)" \
    "$python" -m pip --python "$scratch/venv/bin/python" install -q --only-binary=:all: "${requires[@]}"
for source in "${sources[@]}"; do cp -r "$root/$source" "$scratch/work/"; done
cd "$scratch/work"
"${no_compiler[@]}" "${environment[@]}" /bin/sh -c "$command" >cibuildwheel.log 2>&1 \
    || { cat cibuildwheel.log >&2; fail "cibuildwheel's test-command failed on the installed wheel"; }
tail -n 1 cibuildwheel.log
version="$("${no_compiler[@]}" uplift --version)"
echo "$version"
grep -q "loops: compiled" <<<"$version" || fail "the installed wheel does not run its compiled loops: $version"
# the version from the metadata of the distribution upliftcli (runtime/installed.py), as `python -m upliftcli` says
declared="$("$python" -c 'import sys, tomllib; print(tomllib.load(open(sys.argv[1], "rb"))["project"]["version"])' \
    "$root/pyproject.toml")"
[ "$(head -n 1 <<<"$version")" = "$declared" ] || fail "uplift --version gave $(head -n 1 <<<"$version"), not $declared"
[ "$("${no_compiler[@]}" python -m upliftcli --version | head -n 1)" = "$declared" ] \
    || fail "python -m upliftcli --version does not give $declared"
where="$("${no_compiler[@]}" python -c 'import upliftcli.engines.exact._stepping as m; print(m.__file__)')"
case "$where" in
    "$scratch"/venv/lib/python3*/site-packages/upliftcli/engines/exact/_stepping.abi3.so) ;;
    *) fail "the stepping loop was imported from $where, not the installed wheel's abi3 module" ;;
esac
analyze=(uplift analyze inputs/ten_story_elcentro.toml --engine exact --support uplift --format json)
"${no_compiler[@]}" "${analyze[@]}" >wheel.json || fail "uplift analyze failed with the installed wheel"
# the same analysis by the source tree's install (PYTHON's), where it has one: the same peaks
if "$python" -c "import upliftcli" 2>/dev/null; then
    "$(dirname "$python")/${analyze[0]}" "${analyze[@]:1}" >source.json
else
    cp wheel.json source.json
fi
"$python" - <<'PY' || fail "the analysis of the installed wheel differs from the source tree's"
import json, math
wheel, source = (json.load(open(f"{name}.json")) for name in ("wheel", "source"))
assert wheel["engine"] == "exact" and wheel["support"] == "uplift", wheel.get("engine")
assert math.isfinite(wheel["base_shear"]) and wheel["base_shear"] > 0, wheel["base_shear"]
for field in ("base_shear", "base_moment"):  # the two backends agree to 1e-9 (issue 26), one backend exactly
    assert math.isclose(wheel[field], source[field], rel_tol=1e-9), (field, wheel[field], source[field])
print(f"exact engine, uplift: base shear {wheel['base_shear'] / 1e3:.1f} kN (the source tree's: "
      f"{source['base_shear'] / 1e3:.1f} kN), uplift {wheel['uplift']}")
PY

# The README's first command (its first bash block), from the installed wheel in an empty folder:
# the steps after its `pip install`, with the wheel's venv on PATH in place of .venv/bin/.
readme_steps="$("$python" - "$root/README.md" <<'PY'
import re, sys
first = re.search(r"```bash\n(.*?)\n```", open(sys.argv[1], encoding="utf-8").read(), re.S).group(1).strip()
steps = first.split(" && ")
after = steps[next(i for i, step in enumerate(steps) if " install " in step) + 1:]
print(" && ".join(step.removeprefix(".venv/bin/") for step in after))
PY
)"
grep -q "uplift examples " <<<"$readme_steps" || fail "the README's first command writes no examples: $readme_steps"
mkdir "$scratch/empty"
cd "$scratch/empty"
"${no_compiler[@]}" /bin/sh -c "$readme_steps" >"$scratch/readme.log" 2>&1 \
    || { cat "$scratch/readme.log" >&2; fail "the README's first command failed from the installed wheel: $readme_steps"; }
written="$(find . -mindepth 1 -maxdepth 1 -type d)"
[ "$(wc -l <<<"$written")" -eq 1 ] || fail "the README's first command wrote other folders than the examples': $written"
for folder in inputs records; do
    diff -r "$root/$folder" "$written/$folder" >/dev/null || fail "uplift examples wrote a $folder/ that differs from the repository's"
done
echo "the README's first command from the wheel in an empty folder: $readme_steps"
echo "check_wheel.sh: $(basename "$wheel") installs and runs without a C compiler"
