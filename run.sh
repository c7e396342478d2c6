#!/usr/bin/env bash
# Installs what is missing, builds, and runs the default job: the paper's
# three-link swimmer under closed-loop distributed actuation
# (scenarios/paper.toml). Extra arguments replace the default job's.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$root/scripts/setup.sh"
ipmc_install_packages
ipmc_build "$root"
if [ "$#" -gt 0 ]; then
  exec "$root/build/sim/ipmc-swim" "$@"
fi
exec "$root/build/sim/ipmc-swim" run "$root/scenarios/paper.toml" --out "$root/out/default"
