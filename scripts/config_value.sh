#!/usr/bin/env bash
# config_value.sh SENSOR KEY: the value of KEY in config/SENSOR.yaml (a number without trailing
# zeros: retain_percent 100.0 -> 100), so that make eval and make demo run the model at the
# retention the node runs with, e.g. `config_value.sh radar model` -> image_guided.
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
file="$REPO/config/${1:?usage: config_value.sh radar|lidar KEY}.yaml"
key=${2:?usage: config_value.sh radar|lidar KEY}
value=$(awk -v key="$key:" '$1 == key { v = $2; if (v ~ /^[0-9.]+$/) v = v + 0; print v; exit }' \
  "$file")
if [[ -z "$value" ]]; then
  echo "config_value.sh: $file has no $key" >&2
  exit 2
fi
echo "$value"
