#!/usr/bin/env bash
# config_retention.sh SENSOR: retain_percent of config/SENSOR.yaml as an integer (radar: 100),
# so that make eval and make demo render at the retention the node runs with.
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
file="$REPO/config/${1:?usage: config_retention.sh radar|lidar}.yaml"
value=$(awk '$1 == "retain_percent:" { print $2 + 0; exit }' "$file")
if [[ -z "$value" ]]; then
  echo "config_retention.sh: $file has no retain_percent" >&2
  exit 2
fi
echo "$value"
