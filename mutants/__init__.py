"""Mutation testing of the physics modules (issue 13): the second stage of
``make mutants`` (the quick Python checks on the mutants that survive the
Rust tests) and the report generated from the outcomes of both stages."""
