#!/usr/bin/env bash
# The studio front end's checks: lint and type-check, unit tests, and that its
# sources build to exactly the committed bundle in studio/dist (which the
# server embeds). Installs the locked npm packages first.
set -euo pipefail
cd "$(dirname "$0")/../studio"

npm ci --no-audit --no-fund --loglevel=error >&2
npm run --silent lint
npm run --silent test
npm run --silent build >/dev/null
if ! git diff --quiet -- dist || [ -n "$(git ls-files --others --exclude-standard -- dist)" ]; then
  echo "studio/dist does not match its sources: run 'cd studio && npm run build' and commit dist/" >&2
  git status --short -- dist >&2
  exit 1
fi
echo "studio: lint, unit tests and bundle check passed"
