# Sourced by the device scripts (run from the repository root on the lent GPU machine, with .gl,
# .devlibs and .devbuild carried: docs/render_report.md, "The render suites on the NVIDIA
# driver"): unpacks the Vulkan loader and the carried libraries and validation layer, points the
# loader at the NVIDIA driver, and sets B (the binaries), D (the scattered stone / water volumes of
# raster-transparency-2026-12-05), V (their view at 1080p, 20 frames) and t0.
# .gl: the .debs of libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 (the device
# README's recipe); with libvulkan1 alone the loader cannot open NVIDIA's libGLX_nvidia.so.0.
# .devlibs/libs.tgz: lib/ (what `ldd` of the binaries finds missing there, less glibc and
# libstdc++) and layer/ (libVkLayer_khronos_validation.so and its manifest, whose library_path
# must read "./libVkLayer_khronos_validation.so": a bare name is looked up in the system paths).
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
mkdir -p /tmp/dl && tar xzf .devlibs/libs.tgz -C /tmp/dl
export LD_LIBRARY_PATH=/tmp/dl/lib
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export VK_LAYER_PATH=/tmp/dl/layer
chmod +x .devbuild/*
mkdir -p /work/main/build/release/tools && cp .devbuild/vx /work/main/build/release/tools/vx # The CLI tests' VX_BINARY.
B=$PWD/.devbuild
t0=$(date +%s)
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
D=$(mktemp -d)
python3 docs/render_report/raster-transparency-2026-12-05/make_scatter.py "$D"
V="--dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128 --device gpu --size 1920x1080 --repeat 20"
