#!/usr/bin/env bash
# ctest deploy: systemd's own checker reads the project's units as installed (ExecStart pointed
# at the built binaries) and must find nothing to say: any warning (unknown key, bad value,
# missing binary) fails the test.
# usage: verify_units.sh BIN_DIR DEPLOY_DIR WORK_DIR
set -euo pipefail
bin=${1:?usage: verify_units.sh BIN_DIR DEPLOY_DIR WORK_DIR}
deploy=${2:?}
work=${3:?}
rm -rf "$work"
mkdir -p "$work"
status=0
for unit in mocap-node.service mocap-hub.service; do
    sed "s|/usr/bin/|$bin/|g" "$deploy/$unit" > "$work/$unit"
    if ! out=$(systemd-analyze verify "$work/$unit" 2>&1) || [ -n "$out" ]; then
        echo "verify_units: $unit: $out" >&2
        status=1
    else
        echo "$unit: systemd-analyze verify found nothing to report"
    fi
done
exit $status
