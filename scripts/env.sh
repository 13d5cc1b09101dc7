# Source this file to use the workspace: `source scripts/env.sh` (bash).
# It puts the venv's python3 first on PATH (ahead of pyenv's, which cannot see Debian's ROS
# packages), sources catkin's devel space, and keeps ROS logs and state inside the workspace.
_tamp_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ ! -f "$_tamp_root/devel/setup.bash" ] || [ ! -x "$_tamp_root/.venv/bin/python3" ]; then
  echo "scripts/env.sh: workspace not set up; run scripts/setup (or make setup) first" >&2
  return 1 2>/dev/null || exit 1
fi
export VIRTUAL_ENV="$_tamp_root/.venv"
export PATH="$VIRTUAL_ENV/bin:$PATH"
# shellcheck disable=SC1091
source "$_tamp_root/devel/setup.bash"
export ROS_HOSTNAME=localhost
export ROS_HOME="${ROS_HOME:-$_tamp_root/.ros}"
export ROS_LOG_DIR="${ROS_LOG_DIR:-$ROS_HOME/log}"
export KERAS_BACKEND=torch
export ROS_LANG_DISABLE=gencpp:geneus:genlisp:gennodejs  # messages in Python only (scripts/setup)
export TAMP_WS="$_tamp_root"
unset _tamp_root
