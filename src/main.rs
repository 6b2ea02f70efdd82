//! The `raystep` binary: everything lives in the library's [`raystep::cli`].

fn main() -> std::process::ExitCode {
    raystep::cli::main()
}
