"""quatrot's validation harness: cross-code checks and their report, the
benchmarks' Python side, the long runs and the fixture generators, on shared
references (the packages and which imports which: validation/README.md)."""
