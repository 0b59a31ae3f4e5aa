//! An HTTP server that misbehaves in one chosen way, for the streaming
//! tests: a thread on a free loopback port answering every range request
//! for one file with a 206 whose `Content-Range` is right but whose body is
//! not (see [`Misbehaviour`]), one request per connection, counting the
//! requests. nginx cannot be made to do these: it never encodes a 206 and
//! never sends less than it declares.

use std::io::{BufRead, BufReader, Write};
use std::net::TcpListener;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

#[derive(Debug, Clone, Copy)]
pub enum Misbehaviour {
    /// Says `Content-Encoding: gzip` and sends half the range (as a compressed body would be).
    Gzip,
    /// Declares half the range in `Content-Length` and sends that.
    DeclaredShort,
    /// Declares the whole range, sends half, and closes the connection.
    Cut,
}

pub struct BadServer {
    pub port: u16,
    requests: Arc<AtomicUsize>,
}

impl BadServer {
    /// Serves `file` (its bytes) with `how`; the thread lives as long as the test binary.
    pub fn start(file: Vec<u8>, how: Misbehaviour) -> BadServer {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        let requests = Arc::new(AtomicUsize::new(0));
        let counted = requests.clone();
        std::thread::spawn(move || {
            for stream in listener.incoming() {
                let Ok(mut stream) = stream else { continue };
                let mut reader = BufReader::new(stream.try_clone().unwrap());
                let mut range = None;
                let mut line = String::new();
                while reader.read_line(&mut line).is_ok_and(|n| n > 0) && !line.trim_end().is_empty() {
                    let lower = line.to_ascii_lowercase();
                    if let Some(bytes) = lower.strip_prefix("range:").and_then(|r| r.trim().strip_prefix("bytes=")) {
                        let (a, b) = bytes.split_once('-').unwrap();
                        range = Some((a.parse::<usize>().unwrap(), b.trim().parse::<usize>().unwrap()));
                    }
                    line.clear();
                }
                counted.fetch_add(1, Ordering::SeqCst);
                let (start, last) = range.unwrap_or((0, file.len() - 1));
                let last = last.min(file.len() - 1);
                let body = &file[start..=last];
                let half = &body[..body.len() / 2];
                let (encoding, declared) = match how {
                    Misbehaviour::Gzip => ("Content-Encoding: gzip\r\n", half.len()),
                    Misbehaviour::DeclaredShort => ("", half.len()),
                    Misbehaviour::Cut => ("", body.len()),
                };
                let head = format!(
                    "HTTP/1.1 206 Partial Content\r\nContent-Range: bytes {start}-{last}/{}\r\n{encoding}Content-Length: {declared}\r\nConnection: close\r\n\r\n",
                    file.len()
                );
                let _ = stream.write_all(head.as_bytes());
                let _ = stream.write_all(half);
                let _ = stream.flush();
            }
        });
        BadServer { port, requests }
    }

    pub fn url(&self, path: &str) -> String {
        format!("http://127.0.0.1:{}/{path}", self.port)
    }

    /// Requests answered so far.
    pub fn requests(&self) -> usize {
        self.requests.load(Ordering::SeqCst)
    }
}
