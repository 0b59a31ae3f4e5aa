//! A real HTTP server for the streaming tests: Debian's nginx (installed by
//! `scripts/setup`), started on a free loopback port over a folder and
//! stopped when dropped. `/norange/` serves the same folder with range
//! requests switched off (`max_ranges 0`), as some servers do,
//! `/unavailable/` answers 503 to everything, and `/slow/` serves the folder
//! at 64 KB/s a request (a slow link). [`Nginx::serve_tls`] serves
//! the folder over HTTPS with a given certificate.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

pub struct Nginx {
    child: Child,
    pub port: u16,
    _dir: tempfile::TempDir,
}

impl Nginx {
    /// Serves `root` (files under it at `/NAME`, and again at `/norange/NAME`).
    pub fn serve(root: &Path) -> Nginx {
        Self::start(root, "", "")
    }

    /// Serves `root` over HTTPS with the certificate and key at `cert` and `key` (PEM files).
    pub fn serve_tls(root: &Path, cert: &Path, key: &Path) -> Nginx {
        let tls = format!("ssl_certificate {}; ssl_certificate_key {};", cert.display(), key.display());
        Self::start(root, " ssl", &tls)
    }

    /// nginx on a free port over `root`; `listen` follows the address,
    /// `server` adds to the server block. A free port is one the system
    /// just handed out and took back, so a test running beside this one
    /// may start its server on it too: then one nginx cannot bind it, and
    /// the port answers for the other, which may stop while this test runs.
    /// So nginx also answers on a second port with a token of its own, and
    /// is started again on new ports until its own token comes back.
    fn start(root: &Path, listen: &str, server: &str) -> Nginx {
        let binary = ["/usr/sbin/nginx", "/usr/bin/nginx"]
            .into_iter()
            .map(PathBuf::from)
            .find(|p| p.exists())
            .expect("nginx is installed (scripts/setup installs nginx-light)");
        let dir = tempfile::tempdir().unwrap();
        let started = Instant::now();
        for attempt in 0.. {
            assert!(started.elapsed() < Duration::from_secs(30), "nginx did not start in {attempt} attempts");
            let (port, probe) = (free_port(), free_port());
            let token = format!("pointblend-test-{}-{attempt}-{port}-{probe}", std::process::id());
            let conf = dir.path().join("nginx.conf");
            std::fs::write(&conf, config(dir.path(), root, (port, probe, &token), (listen, server))).unwrap();
            let mut child = Command::new(&binary)
                .arg("-p")
                .arg(dir.path())
                .arg("-c")
                .arg(&conf)
                .arg("-e")
                .arg(dir.path().join("stderr.log"))
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("nginx starts");
            let tried = Instant::now();
            while tried.elapsed() < Duration::from_secs(5) && matches!(child.try_wait(), Ok(None)) {
                match answer(probe) {
                    Some(answer) if answer.contains(&token) => return Nginx { child, port, _dir: dir },
                    // Another server holds the port: start again on others.
                    Some(_) => break,
                    None => std::thread::sleep(Duration::from_millis(20)),
                }
            }
            let _ = child.kill();
            let _ = child.wait();
        }
        unreachable!("the loop returns or fails its assertion")
    }

    pub fn url(&self, path: &str) -> String {
        format!("http://127.0.0.1:{}/{path}", self.port)
    }
}

/// A port the system hands out as free (and takes back).
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

/// The configuration: the folder at `port`, and `token` answered at `probe`.
fn config(dir: &Path, root: &Path, (port, probe, token): (u16, u16, &str), (listen, server): (&str, &str)) -> String {
    let (d, root) = (dir.display(), root.display());
    format!(
        "daemon off; master_process off; pid {d}/nginx.pid; error_log {d}/error.log;
events {{}}
http {{
  access_log off;
  client_body_temp_path {d}/body; proxy_temp_path {d}/proxy; fastcgi_temp_path {d}/fastcgi;
  uwsgi_temp_path {d}/uwsgi; scgi_temp_path {d}/scgi;
  server {{
    listen 127.0.0.1:{port}{listen};
    root {root};
    {server}
    location /norange/ {{ alias {root}/; max_ranges 0; }}
    location /unavailable/ {{ return 503; }}
    location /slow/ {{ alias {root}/; limit_rate 64k; }}
  }}
  server {{
    listen 127.0.0.1:{probe};
    location / {{ return 200 \"{token}\"; }}
  }}
}}
"
    )
}

/// What the server at `port` answers to a plain GET, or `None` when nothing answers.
/// Written over a socket, not with an HTTP client: a probe must tell
/// "nothing listens yet" from "another server answers" (any status), and
/// `ureq` is not among the tests' dependencies.
fn answer(port: u16) -> Option<String> {
    use std::io::{Read, Write};
    let mut stream = std::net::TcpStream::connect(("127.0.0.1", port)).ok()?;
    stream.set_read_timeout(Some(Duration::from_secs(2))).ok()?;
    stream.write_all(b"GET / HTTP/1.0\r\nHost: localhost\r\n\r\n").ok()?;
    let mut text = String::new();
    stream.read_to_string(&mut text).ok()?;
    Some(text)
}

impl Drop for Nginx {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
