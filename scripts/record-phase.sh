#!/usr/bin/env bash
# Appends "NAME<tab>SECONDS" to the file $BOUNCE_PHASE_LOG names, if any
# (.ci/run sets it and prints the phases at its end); does nothing otherwise.
#   scripts/record-phase.sh NAME SECONDS
set -euo pipefail
[ -n "${BOUNCE_PHASE_LOG:-}" ] || exit 0
printf '%s\t%s\n' "$1" "$2" >> "$BOUNCE_PHASE_LOG"
