//! The `zenosim` command. Its work is done by the library `zenosim_cli` (`src/lib.rs`), so that
//! the fuzz targets and the tests can reach its parts.

fn main() -> std::process::ExitCode {
    zenosim_cli::main()
}
