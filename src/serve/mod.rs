//! `glint serve`: a local web page that shows the scene's picture and
//! renders it again on every save of the scene file or of a texture or
//! mesh it uses (a coarse preview at once, then the full image, then the
//! AOVs), with the pixel under the pointer explained. The page, its
//! script and style are built in; the API it uses is documented in
//! `docs/serve.md`. Every request must carry the random token of the URL.

mod events;
mod file_watch;
#[cfg(unix)]
mod gate;
mod http;
mod picture;
mod rays;
mod routes;
mod state;
mod version;
mod worker;

use crate::render::RenderOptions;
use crate::scene::Dialect;
use http::App;
use state::Shared;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
#[cfg(unix)]
use std::os::unix::fs::DirBuilderExt;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// How to serve a scene.
#[derive(Clone, Debug)]
pub struct ServeOptions {
    /// The scene file.
    pub scene: PathBuf,
    /// The address to listen on (127.0.0.1 unless told otherwise).
    pub bind: IpAddr,
    /// The port (0: a free one).
    pub port: u16,
    /// How to render (sizes, samples, seed, threads); its AOVs and region are not used.
    pub render: RenderOptions,
    /// The lineage to read the file as (`None`: by its markers).
    pub dialect: Option<Dialect>,
    /// Their own render to compare with (`--compare THEIRS.bmp`).
    pub compare: Option<PathBuf>,
}

impl ServeOptions {
    /// Serving `scene` on 127.0.0.1 at a free port, rendered as `glint render` does.
    pub fn new(scene: impl Into<PathBuf>) -> ServeOptions {
        ServeOptions {
            scene: scene.into(),
            bind: IpAddr::V4(Ipv4Addr::LOCALHOST),
            port: 0,
            render: RenderOptions::default(),
            dialect: None,
            compare: None,
        }
    }
}

/// Why the server could not start.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The scene file is not there or not a regular file.
    #[error("{0}")]
    Scene(String),
    /// Their picture cannot be read.
    #[error("{0}")]
    Compare(String),
    /// The address cannot be listened on.
    #[error("cannot listen on {addr}: {message}")]
    Bind {
        /// The address.
        addr: SocketAddr,
        /// Why not.
        message: String,
    },
}

/// A running server: its threads watch, render and answer until the process ends.
pub struct Server {
    addr: SocketAddr,
    token: String,
    /// The private folder of the inner socket, removed when serving ends.
    private: Option<PathBuf>,
}

impl Server {
    /// Checks the scene file, reads their picture, listens, and starts the
    /// watcher, the render worker and the request threads.
    pub fn start(options: ServeOptions) -> Result<Server, ServeError> {
        match std::fs::metadata(&options.scene) {
            Ok(m) if m.is_file() => {}
            Ok(_) => {
                return Err(ServeError::Scene(format!(
                    "{} is not a regular file",
                    options.scene.display()
                )));
            }
            Err(e) => {
                return Err(ServeError::Scene(format!(
                    "cannot read the scene file {}: {e}",
                    options.scene.display()
                )));
            }
        }
        let theirs = match &options.compare {
            Some(path) => Some(crate::read_picture(path).map_err(ServeError::Compare)?),
            None => None,
        };
        let theirs_png = match &theirs {
            Some((rgb, (w, h))) => {
                let pixels = rgb
                    .chunks(3)
                    .map(|p| {
                        let c = |k: usize| (f32::from(p[k]) + 0.5) / 255.0;
                        [c(0), c(1), c(2)]
                    })
                    .collect();
                let png = crate::Image::from_pixels(*w, *h, pixels)
                    .encode(crate::Format::Png)
                    .map_err(ServeError::Compare)?;
                Some(Arc::new(png))
            }
            None => None,
        };
        let addr = SocketAddr::new(options.bind, options.port);
        let cannot = |e: &dyn std::fmt::Display| ServeError::Bind {
            addr,
            message: e.to_string(),
        };
        let listener = std::net::TcpListener::bind(addr).map_err(|e| cannot(&e))?;
        let addr = listener.local_addr().map_err(|e| cannot(&e))?;
        let token = token();
        #[cfg(unix)]
        let (server, private) = {
            // tiny_http listens on a Unix socket in a folder only we can
            // enter; the gate relays the public socket to it.
            let private = std::env::temp_dir().join(format!(
                "glint-serve-{}-{}",
                std::process::id(),
                &token[..8]
            ));
            let made = std::fs::DirBuilder::new().mode(0o700).create(&private);
            made.map_err(|e| cannot(&format!("cannot make {}: {e}", private.display())))?;
            let socket = private.join("http.sock");
            let server = tiny_http::Server::http_unix(&socket).map_err(|e| cannot(&e))?;
            spawn("glint-gate", move || gate::accept_loop(&listener, &socket));
            (server, Some(private))
        };
        #[cfg(not(unix))]
        let (server, private) = (
            tiny_http::Server::from_listener(listener, None).map_err(|e| cannot(&e))?,
            None,
        );
        let shared = Arc::new(Shared::new(
            options.scene.clone(),
            theirs_png,
            options.render.clone(),
        ));
        let watch = Arc::new(Mutex::new(file_watch::FileWatch::default()));
        let trigger = Arc::new(worker::Trigger::new());
        let config = worker::Config {
            dialect: options.dialect,
            theirs,
        };
        {
            let (watch, trigger) = (watch.clone(), trigger.clone());
            spawn("glint-watch", move || worker::watch_loop(&watch, &trigger));
        }
        {
            let shared = shared.clone();
            spawn("glint-render", move || {
                worker::work_loop(&shared, &config, &watch, &trigger)
            });
        }
        let app = Arc::new(App::new(shared, token.clone(), server));
        for _ in 0..http::WORKERS {
            let app = app.clone();
            spawn("glint-http", move || http::serve_loop(&app));
        }
        Ok(Server {
            addr,
            token,
            private,
        })
    }

    /// The address it listens on.
    pub fn address(&self) -> SocketAddr {
        self.addr
    }

    /// The token every request must carry (`?token=` or `X-Glint-Token:`).
    pub fn token(&self) -> &str {
        &self.token
    }

    /// The page's URL, with the token.
    pub fn url(&self) -> String {
        format!("http://{}/?token={}", self.addr, self.token)
    }

    /// Serves until `stop` is set (by a signal handler), then removes its
    /// private folder; the threads end with the process.
    pub fn serve_until(self, stop: &AtomicBool) {
        while !stop.load(Ordering::Relaxed) {
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        if let Some(dir) = &self.private {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

/// Starts a named thread (one that cannot be started leaves the server
/// without it, which the page shows as nothing happening; the system is
/// out of threads then anyway).
fn spawn(name: &str, f: impl FnOnce() + Send + 'static) {
    let _ = std::thread::Builder::new().name(name.to_string()).spawn(f);
}

/// 128 random bits as hex: from the system's random source, or else from
/// std's randomly keyed hasher.
fn token() -> String {
    use std::hash::{BuildHasher, Hasher};
    let mut bytes = [0u8; 16];
    let from_system = std::fs::File::open("/dev/urandom")
        .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut bytes))
        .is_ok();
    if !from_system {
        for (i, chunk) in bytes.chunks_mut(8).enumerate() {
            let mut h = std::collections::hash_map::RandomState::new().build_hasher();
            h.write_usize(i);
            h.write_u128(
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_nanos()),
            );
            chunk.copy_from_slice(&h.finish().to_le_bytes());
        }
    }
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
