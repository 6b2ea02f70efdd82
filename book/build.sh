#!/usr/bin/env bash
# Builds the raystep book into target/book/ and checks its links: see build.py.
exec python3 "$(dirname "$0")/build.py" "$@"
