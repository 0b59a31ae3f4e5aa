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

    /// nginx on a free port over `root`; `listen` follows the address, `server` adds to the server block.
    fn start(root: &Path, listen: &str, server: &str) -> Nginx {
        let binary = ["/usr/sbin/nginx", "/usr/bin/nginx"]
            .into_iter()
            .map(PathBuf::from)
            .find(|p| p.exists())
            .expect("nginx is installed (scripts/setup installs nginx-light)");
        let dir = tempfile::tempdir().unwrap();
        let port = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
        let d = dir.path().display();
        let root = root.display();
        let config = format!(
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
}}
"
        );
        let conf = dir.path().join("nginx.conf");
        std::fs::write(&conf, config).unwrap();
        let child = Command::new(binary)
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
        let started = Instant::now();
        while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(started.elapsed() < Duration::from_secs(10), "nginx did not listen on {port}");
            std::thread::sleep(Duration::from_millis(20));
        }
        Nginx { child, port, _dir: dir }
    }

    pub fn url(&self, path: &str) -> String {
        format!("http://127.0.0.1:{}/{path}", self.port)
    }
}

impl Drop for Nginx {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
