//! Standard output and error that cannot be written (`> /dev/full`, a closed descriptor): an
//! error with its own exit code (74, EX_IOERR), never a panic or a silent success.

use std::process::ExitCode;

/// A standard output or error that cannot be written (`> /dev/full`, a closed descriptor) is an
/// error with its own exit code (74, EX_IOERR), never a panic: `print!` panics on a failed write
/// ("failed printing to stdout"), and this hook turns exactly that into one line and the exit.
pub fn quiet_on_failed_output() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let msg = (info.payload().downcast_ref::<String>().map(String::as_str))
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        for stream in ["stdout", "stderr"] {
            if let Some(why) = msg.strip_prefix(&format!("failed printing to {stream}: ")) {
                use std::io::Write as _;
                let line = format!("deckspin: cannot write to {stream}: {why}\n");
                let _ = std::io::stderr().write_all(line.as_bytes());
                std::process::exit(74);
            }
        }
        default(info);
    }));
}

/// clap's own exit for `--help`, `--version` and usage errors, except that help or a version
/// that cannot be written to stdout (`> /dev/full`) is an error (74), not a silent success.
pub fn clap_exit(e: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if !matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
        e.exit();
    }
    use std::io::Write as _;
    let text = e.render().to_string();
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) if err.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("deckspin: cannot write to stdout: {err}");
            ExitCode::from(74)
        }
    }
}
