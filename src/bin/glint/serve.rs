//! `glint serve`: the live page of a scene.

use crate::args::{DialectArg, PhotonArgs, PixelArgs, thread_count};
use crate::{Failure, fail, say};
use glint::RenderOptions;
use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// The arguments of `glint serve`.
#[derive(clap::Args)]
pub struct Args {
    /// The scene file.
    scene: PathBuf,
    /// The port to listen on (0: a free one).
    #[arg(long, default_value_t = 0)]
    port: u16,
    /// The address to listen on. Anything but a loopback address lets
    /// anyone who can reach it and knows the token read the scene.
    #[arg(long, default_value = "127.0.0.1")]
    bind: std::net::IpAddr,
    /// Open the page in the desktop's browser (xdg-open or open).
    #[arg(long)]
    open: bool,
    /// Your own render of the scene (.bmp or .png) to compare with, on a slider.
    #[arg(long)]
    compare: Option<PathBuf>,
    /// Worker threads, as for `render`.
    #[arg(long, value_parser = thread_count)]
    threads: Option<usize>,
    #[command(flatten)]
    pixels: PixelArgs,
    #[command(flatten)]
    dialect: DialectArg,
    #[command(flatten)]
    photons: PhotonArgs,
}

/// Serves the page until a signal arrives (the only way it ends).
pub fn exec(args: Args, interrupt: &AtomicBool) -> Result<(), Failure> {
    let options = glint::serve::ServeOptions {
        scene: args.scene.clone(),
        bind: args.bind,
        port: args.port,
        render: args.pixels.apply(RenderOptions {
            threads: args.threads,
            photons: args.photons.options(),
            ..RenderOptions::default()
        }),
        dialect: args.dialect.dialect,
        compare: args.compare.clone(),
    };
    let server = glint::serve::Server::start(options).map_err(|e| fail(format!("error: {e}")))?;
    let addr = server.address();
    if !addr.ip().is_loopback() {
        say(&format!(
            "warning: listening on {}: anyone who can reach this address and knows the token \
             can read the scene and the files it uses (the default, 127.0.0.1, keeps it on this machine)",
            addr.ip()
        ));
    }
    let url = server.url();
    // One line on stdout, for people and scripts; the rest on stderr.
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{url}");
    let _ = out.flush();
    drop(out);
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .ok()
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "THIS-MACHINE".to_string());
    // The tunnel's far end: the address listened on (loopback for 0.0.0.0 or ::).
    let target = if addr.ip().is_unspecified() {
        "127.0.0.1".to_string()
    } else {
        match addr.ip() {
            std::net::IpAddr::V6(ip) => format!("[{ip}]"),
            ip => ip.to_string(),
        }
    };
    say(&format!(
        "from another machine: ssh -L {port}:{target}:{port} {host}   then open http://127.0.0.1:{port}/?token={token}",
        port = addr.port(),
        token = server.token()
    ));
    if args.open {
        for opener in ["xdg-open", "open"] {
            let started = std::process::Command::new(opener)
                .arg(&url)
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::null())
                .spawn();
            if started.is_ok() {
                break;
            }
        }
    }
    server.serve_until(interrupt);
    Err(Failure::Interrupted)
}
