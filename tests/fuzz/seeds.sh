#!/usr/bin/env bash
# Seeds of the fuzz targets into BUILD_DIR/corpus/TARGET (kept with what earlier runs found), and
# the dictionaries BUILD_DIR/corpus/*.dict: shipped scenes (and small versions of the large ones,
# which fuzz faster), shipped scripts, the seeds of tests/fuzz/seeds, checkpoints and dictionaries
# from fuzz_seeds, and the inputs of tests/fuzz/crashes.
# Usage: tests/fuzz/seeds.sh BUILD_DIR
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1/corpus
mkdir -p "$out"/{command_parser,scene,checkpoint,session,repl}
# The parser's corpus of the earlier layout (files right under corpus/) goes where it now belongs.
find "$out" -maxdepth 1 -type f ! -name '*.dict' -exec mv -t "$out/command_parser" {} +

# The command parser: every line of the shipped scripts.
n=0
for f in scenes/*.silt tests/fuzz/seeds/*.silt; do
  while IFS= read -r line; do
    printf '%s' "$line" > "$out/command_parser/seed_$n"
    n=$((n + 1))
  done < "$f"
done

# Scenes: the shipped ones, and the large ones made small.
cp scenes/*.toml tests/fuzz/seeds/*.toml tests/fuzz/crashes/*.toml "$out/scene/"
sed 's/40\.0, 20\.0/4.0, 4.0/g' scenes/chute.toml > "$out/scene/small_chute.toml"
sed 's/^count = 1600/count = 60/' scenes/silo.toml > "$out/scene/small_silo.toml"
sed 's/^count = 1000/count = 40/' scenes/shear3d_frictionless.toml > "$out/scene/small_shear3d.toml"
sed 's/^count = 896/count = 60/' scenes/shear2d_dry.toml > "$out/scene/small_shear2d.toml"

# Checkpoints and dictionaries; and what the targets found (crashes/), run again at every start.
"$1/tests/fuzz/fuzz_seeds" "$1/fuzz_seeds"
cp "$1"/fuzz_seeds/checkpoint/*.ckpt tests/fuzz/crashes/*.ckpt "$out/checkpoint/"
cp "$1"/fuzz_seeds/*.dict "$out/"
cp tests/fuzz/crashes/*.session "$out/session/"
cp tests/fuzz/crashes/*.keys "$out/repl/"

# Sessions: the first byte picks the scene loaded first (0 to 3: pack_2d, bounce_dry,
# collision_normal, none; 7 paste_iso, 11 cavity_2d), the rest are the lines of a script; on a
# terminal the same lines typed, and some keys.
for f in scenes/*.silt tests/fuzz/seeds/*.silt; do
  for s in 00 01 02 03 07 0b; do
    { printf "\\x$s"; cat "$f"; } > "$out/session/seed_${s}_$(basename "$f" .silt)"
    cp "$out/session/seed_${s}_$(basename "$f" .silt)" "$out/repl/"
  done
done
keys() { printf "$2" > "$out/repl/seed_keys_$1"; }
keys complete '\x00ru\t 5\npr\tt\tke\nset cont\t\t0.2\nload pa\t\n'   # Tab: commands, observables, keys, files
keys history '\x00run 3\nprint t\n\x1b[A\x1b[A\n\x10\x0e\nrun\x1b[5~\n'  # arrows, Ctrl-P/N, Page Up
keys editing '\x00print t\x01hash # \x05\x02\x02\x06\x08\x0b\x15print step\x17\x19\n\x1bbx\x1bf\x1bd\n'
keys vi '\x00\x1b\x0aiprint t\x1b0cwhash\x1b\n\x1b\x0a\n'            # vi mode on and off (M-C-j)
keys quoted '\x00print\x16\x01 t\x11\x02\n\x03\x04'                     # quoted insert, Ctrl-C, Ctrl-D
