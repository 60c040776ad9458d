//! `tracer mesh`'s flags: the plan (every refusal before any work) never panics.

use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The CLI's plan (every refusal before any work) never panics on any flag value.
    #[test]
    fn mesh_flags_never_panic(
        depth in "\\PC{0,6}",
        max_depth in prop::option::of("[0-9-]{0,4}"),
        domain in prop::option::of("[-0-9.,e]{0,30}"),
        stats in "[a-z]{0,5}",
        arith in "[a-zA-Z*]{0,6}",
        out in "[a-z./]{0,12}",
    ) {
        let args = tracer_cli::mesh::MeshArgs {
            src: tracer_cli::args::ModelArgs { expr: Some("1 - x^2 - y^2 - z^2".into()), ..Default::default() },
            out: Some(std::env::temp_dir().join("tracer-mesh-prop").join(out)),
            depth,
            max_depth,
            arith,
            domain,
            threads: None,
            stats,
            no_check: false,
            no_merge: false,
            no_branch_planes: false,
            quiet: true,
        };
        let _ = tracer_cli::mesh::plan(&args);
    }
}
