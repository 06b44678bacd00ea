# The device machine's set-up that calls 60-63 ran first (sourced; moved here from each script):
# the Vulkan loader's .debs unpacked, the carried libraries on the path, NVIDIA's ICD.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
mkdir -p /tmp/dl && tar xzf .devlibs/libs.tgz -C /tmp/dl
export LD_LIBRARY_PATH=/tmp/dl/lib
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
