//! Shared property-test kit (enabled by the `testkit` feature): proptest strategies
//! for input ranges, random expression trees, and a multi-precision reference evaluator.
