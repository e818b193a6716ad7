#!/bin/sh
# A stand-in for mpiexec in retry_lsan_tracer_test.cmake: `fake_mpiexec.sh -n RANKS ... SCENARIO`
# counts its calls in the file $FAKE_MPIEXEC_CALLS and prints what a suite would in SCENARIO.
for last; do :; done
calls=$(($(cat "$FAKE_MPIEXEC_CALLS" 2>/dev/null || echo 0) + 1))
echo "$calls" >"$FAKE_MPIEXEC_CALLS"
tracer_crash() {
    echo "[  PASSED  ] 2 tests."
    echo "Tracer caught signal 11: addr=0x0 pc=0x0 sp=0x0" >&2
    echo "==1==LeakSanitizer has encountered a fatal error." >&2
    exit 1
}
case "$last" in
tracer-once) [ "$calls" -eq 1 ] && tracer_crash; echo "[  PASSED  ] 2 tests."; exit 0 ;;
tracer-always) tracer_crash ;;
failed-then-tracer) echo "[  FAILED  ] Suite.Case"; tracer_crash ;;
leak) echo "[  PASSED  ] 2 tests."; echo "ERROR: LeakSanitizer: detected memory leaks" >&2; exit 23 ;;
no-tests) echo "Tracer caught signal 11" >&2; echo "LeakSanitizer has encountered a fatal error." >&2; exit 1 ;;
esac
exit 2
