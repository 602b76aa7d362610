"""quatrot's validation harness: cross-code checks, fixture generators, report."""
