#!/usr/bin/env bash
# Builds the two test drivers Debian's kernel does not ship, vimc.ko (the virtual media-controller
# camera libcamera has a pipeline handler for) and gpio-sim.ko (a simulated GPIO chip driven
# through configfs/sysfs), out of tree from Debian's linux-source-6.1 tarball against the
# linux-headers of kernel KVER. gpio-sim needs kernel/irq/irq_sim.c (CONFIG_IRQ_SIM, not built by
# Debian): it is compiled into the same module, its one call of irq_to_desc() (not exported to
# modules in 6.1) replaced by the exported generic_handle_irq(), which runs the same handler.
# The result is cached in CACHE_DIR/KVER/ with a stamp naming the tarball and headers it came
# from; a second run with the same inputs does nothing.
# Usage: build_modules.sh KVER|--newest-with-vivid CACHE_DIR   prints the module directory
# (--newest-with-vivid: the kernel run_kernel.sh boots, the newest with vivid and headers).
# Exit 77 (ctest SKIP) with the reason when a package is missing; 1 when the build fails.
set -euo pipefail

kver=$1
cache=$2
if [ "$kver" = --newest-with-vivid ]; then
    kver=$("$(dirname "$0")/boot_kernel.sh") || {
        echo "*** kernel modules not built: no /boot/vmlinuz-* with vivid and its linux-headers ***" >&2
        echo "*** (deploy/install-deps.sh installs linux-image-amd64 and linux-headers-amd64) ***" >&2
        exit 77
    }
fi
mkdir -p "$cache"
cache=$(cd "$cache" && pwd) # kbuild's M= must be absolute
out=$cache/$kver

skip() {
    echo "*** kernel modules not built: $* ***" >&2
    echo "*** (deploy/install-deps.sh installs linux-source-6.1 and linux-headers-$kver) ***" >&2
    exit 77
}

tarball=$(ls /usr/src/linux-source-6.1.tar.xz /usr/src/linux-source-6.1.tar.bz2 2>/dev/null | head -n 1 || true)
[ -n "$tarball" ] || skip "no /usr/src/linux-source-6.1.tar.* (package linux-source-6.1)"
headers=/lib/modules/$kver/build
[ -f "$headers/Makefile" ] || skip "no $headers/Makefile (package linux-headers-$kver)"
command -v make >/dev/null || skip "make is not installed"

stamp="$(stat -c '%n %s %Y' "$tarball") $(stat -L -c '%s %Y' "$headers/Module.symvers") $(sha256sum "$0" | cut -c1-16)"
if [ -f "$out/stamp" ] && [ "$(cat "$out/stamp")" = "$stamp" ] && [ -f "$out/vimc.ko" ] &&
    [ -f "$out/gpio-sim.ko" ]; then
    echo "$out"
    exit 0
fi

rm -rf "$out"
src=$out/src
mkdir -p "$src"
top=linux-source-6.1
echo "kernel modules: extracting vimc, gpio-sim and irq_sim from $tarball" >&2
tar -C "$src" -xf "$tarball" --wildcards "$top/drivers/media/test-drivers/vimc/*" \
    "$top/drivers/gpio/gpio-sim.c" "$top/drivers/gpio/gpiolib.h" "$top/kernel/irq/irq_sim.c"

# vimc: its own Makefile, with the Kconfig symbol the headers' .config does not set made obj-m.
vimc=$src/$top/drivers/media/test-drivers/vimc
sed -i 's/obj-$(CONFIG_VIDEO_VIMC)/obj-m/' "$vimc/Makefile"
grep -q '^obj-m += vimc.o' "$vimc/Makefile" || { echo "vimc Makefile not as expected" >&2; exit 1; }

# gpio-sim: gpio-sim.c (renamed so the module can keep the name gpio-sim), the private
# gpiolib.h it includes, and irq_sim.c with the one unexported call replaced.
gsim=$src/gpio-sim
mkdir -p "$gsim"
cp "$src/$top/drivers/gpio/gpio-sim.c" "$gsim/gpio-sim-main.c"
cp "$src/$top/drivers/gpio/gpiolib.h" "$gsim/gpiolib.h"
sed 's/handle_simple_irq(irq_to_desc(irqnum));/generic_handle_irq(irqnum);/' \
    "$src/$top/kernel/irq/irq_sim.c" >"$gsim/irq_sim.c"
if grep -q irq_to_desc "$gsim/irq_sim.c"; then
    echo "irq_sim.c still calls irq_to_desc(): the source changed, update $0" >&2
    exit 1
fi
cat >"$gsim/Makefile" <<'EOF'
obj-m += gpio-sim.o
gpio-sim-y := gpio-sim-main.o irq_sim.o
EOF

for dir in "$vimc" "$gsim"; do
    echo "kernel modules: building $dir against $headers" >&2
    if ! make -s -C "$headers" M="$dir" modules >"$out/build.log" 2>&1; then
        cat "$out/build.log" >&2
        echo "kernel modules: build of $dir failed" >&2
        exit 1
    fi
done
cp "$vimc/vimc.ko" "$gsim/gpio-sim.ko" "$out/"
for m in vimc gpio-sim; do
    magic=$(modinfo -F vermagic "$out/$m.ko")
    case "$magic" in
    "$kver "*) ;;
    *) echo "$m.ko has vermagic '$magic', not for $kver" >&2; exit 1 ;;
    esac
done
rm -rf "$src"
echo "$stamp" >"$out/stamp"
echo "$out"
