#!/bin/bash
# Lavapipe (this VM), stop 51: the denoiser's albedo guide seen through see-through blocks. Two
# 32x8x32 u8 volumes: a checker of single water blocks on grass (tint edges everywhere) and a
# two-step pond. Reference: 16 spp x 48 frames (plain mean, sample seed 1000) by OLD_VX (the raw
# path is the same in both: checked by cmp of the 4 spp raw images); then 4 spp denoised and raw,
# sample seeds 1 and 2, by each binary. RMSE of the 8-bit images (scripts/measure_sampling.py's
# PNG reader).
# Usage (repository root): bash docs/render_report/see-through-body-2026-12-05/tint_guide.sh OLD_VX NEW_VX
set -u
OLD=$1 NEW=$2
D=$(mktemp -d)
python3 - "$D" <<'PY'
import sys
X, Y, Z = 32, 8, 32
for name in ("checker", "pond"):
    v = bytearray(X * Y * Z)
    for z in range(Z):
        for x in range(X):
            for y in range(4):
                v[x + X * (y + Y * z)] = 1 if y < 3 else 3
            if name == "checker" and (x // 2 + z // 2) % 2 == 0 and 4 <= x < 28 and 4 <= z < 28:
                v[x + X * (4 + Y * z)] = 5
            if name == "pond" and 8 <= x < 24 and 8 <= z < 24:
                v[x + X * (3 + Y * z)] = 5
                if 12 <= x < 20 and 12 <= z < 20:
                    v[x + X * (2 + Y * z)] = 5
    open(sys.argv[1] + "/" + name + ".raw", "wb").write(v)
PY
declare -A VIEW=([checker]="--eye 16,16,-4 --target 16,3,14" [pond]="--eye 16,14,-6 --target 16,2,16")
for sc in checker pond; do
  V="--raw $D/$sc.raw --dims 32,8,32 --type u8 ${VIEW[$sc]} --size 320x180"
  "$OLD" render $V --spp 16 --accumulate 48 --history-clamp off --sample-seed 1000 --out "$D/${sc}_ref.png" > /dev/null
  for bin in old new; do
    vx=$OLD; [ $bin = new ] && vx=$NEW
    for seed in 1 2; do
      "$vx" render $V --spp 4 --denoise on --sample-seed $seed --out "$D/${sc}_denoised_${bin}_$seed.png" > /dev/null
      "$vx" render $V --spp 4 --sample-seed $seed --out "$D/${sc}_raw_${bin}_$seed.png" > /dev/null
    done
  done
  cmp -s "$D/${sc}_raw_old_1.png" "$D/${sc}_raw_new_1.png" && echo "$sc: 4 spp raw identical in both"
  python3 - "$D" "$sc" <<'PY'
import sys
sys.path.insert(0, "scripts")
from measure_sampling import read_png
d, sc = sys.argv[1], sys.argv[2]
ref = read_png(f"{d}/{sc}_ref.png")
def rmse(p):
    img = read_png(p)
    return (sum((a - b) ** 2 for a, b in zip(ref, img)) / len(ref)) ** 0.5
for kind in ("raw", "denoised"):
    for bin in ("old", "new"):
        print(f"{sc} 4 spp {kind:8s} {bin}: " + " / ".join("%.5f" % rmse(f"{d}/{sc}_{kind}_{bin}_{s}.png") for s in (1, 2)))
PY
done
rm -rf "$D"
