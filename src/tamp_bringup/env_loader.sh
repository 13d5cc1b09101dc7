#!/usr/bin/env bash
# roslaunch env-loader of the fleet's <machine> tags (launch/fleet_sim.launch): the workspace's
# environment (scripts/env.sh), then the node's command. On another host roslaunch runs it over
# ssh, so the workspace must be built there at the same path, or TAMP_WS must name it.
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ws="${TAMP_WS:-${here%/src/tamp_bringup}}"
# shellcheck disable=SC1091
source "$ws/scripts/env.sh" || exit 1
# a remote machine speaks for itself on the shared master (env.sh sets localhost)
[ -z "${TAMP_ROS_HOSTNAME:-}" ] || export ROS_HOSTNAME="$TAMP_ROS_HOSTNAME"
exec "$@"
