#!/usr/bin/env bash
# Prints the ctest -E pattern of the offload test runs (.ci/run stage 3, bench/gpu_check.sh):
# tests/offload_excluded_tests.txt without its comments, joined with '|'.
grep -v '^#' "$(dirname "$0")/offload_excluded_tests.txt" | paste -sd'|'
