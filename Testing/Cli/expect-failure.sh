#!/usr/bin/env bash
# expect-failure.sh REGEX COMMAND...: passes when COMMAND exits non-zero (not by a signal) and its stderr matches
# REGEX; fails when it succeeds, crashes, or says something else. With EXPECT_STATUS set in the environment, the exit
# status must also equal it (tissuemosaic: 2 for a command line that does not make sense, 1 for other errors).
set -u
regex=$1; shift
stderr=$("$@" 2>&1 >/dev/null)
status=$?
echo "exit status $status; stderr: $stderr"
if [ "$status" -eq 0 ]; then echo "FAIL: the command succeeded"; exit 1; fi
if [ "$status" -ge 128 ]; then echo "FAIL: the command was killed by a signal (crash)"; exit 1; fi
if [ -n "${EXPECT_STATUS:-}" ] && [ "$status" -ne "$EXPECT_STATUS" ]; then
  echo "FAIL: exit status $status, expected $EXPECT_STATUS"; exit 1
fi
if ! grep -Eq -- "$regex" <<<"$stderr"; then echo "FAIL: stderr does not match /$regex/"; exit 1; fi
echo "ok: non-zero exit with the expected message"
