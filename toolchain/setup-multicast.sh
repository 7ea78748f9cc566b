#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# LCM's UDP multicast (udpm://239.255.76.67:7667?ttl=0) needs a route for 224.0.0.0/4. A machine
# without a default route (a CI container, an offline rig) has none: route multicast over the
# loopback interface then. Changes nothing when a route exists.
set -euo pipefail
group=239.255.76.67
if ip route get "$group" >/dev/null 2>&1; then
    exit 0
fi
if [[ $EUID -ne 0 ]]; then
    echo "setup-multicast: no route for $group; as root run:" >&2
    echo "    ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo" >&2
    exit 1
fi
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo
echo "setup-multicast: routed 224.0.0.0/4 over lo for LCM"
