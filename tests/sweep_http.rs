//! HTTP failures that another try would meet again are refused at once, in
//! one line, without the retries and their backoff (0.25 + 0.5 + 1 + 2 s): a
//! refused connection, a certificate the client does not trust (nginx with
//! a self-signed one), a range sent encoded (gzip) and a body its server
//! declares shorter than its range. A connection cut in the middle of a
//! body is still retried.

mod common;

use std::process::{Command, Output};
use std::time::{Duration, Instant};

use common::bad_http::{BadServer, Misbehaviour};
use common::nginx::Nginx;

fn sample() -> Option<Vec<u8>> {
    Some(std::fs::read(common::shared_data("lidar/1.2-with-color.copc.laz")?).unwrap())
}

fn info(url: &str) -> (Output, Duration) {
    let started = Instant::now();
    let output = Command::new(env!("CARGO_BIN_EXE_pointblend")).arg("info").arg(url).output().expect("pointblend runs");
    (output, started.elapsed())
}

/// The one error line of `info URL`, which must fail at once: no retry, at most three lines on stderr, no panic.
fn refused_at_once(url: &str, what: &str) -> String {
    let (output, took) = info(url);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "{what} was accepted: {stderr}");
    assert!(!stderr.contains("panicked") && !stderr.contains("retrying"), "{what}: {stderr}");
    assert!(stderr.lines().count() <= 3, "{what}: {} lines on stderr: {stderr}", stderr.lines().count());
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "{what}: {stderr}");
    assert!(took < Duration::from_secs(2), "{what} took {took:?}");
    errors[0].to_string()
}

#[test]
fn a_refused_connection_fails_at_once() {
    let closed = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
    let line = refused_at_once(&format!("http://127.0.0.1:{closed}/tile.copc.laz"), "a closed port");
    assert!(line.to_lowercase().contains("connection refused"), "{line}");
}

#[test]
fn an_untrusted_certificate_fails_at_once() {
    let file = require!(sample());
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tile.copc.laz"), file).unwrap();
    let (cert, key) = (dir.path().join("cert.pem"), dir.path().join("key.pem"));
    let made = Command::new("openssl")
        .args(["req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj", "/CN=127.0.0.1"])
        .arg("-keyout")
        .arg(&key)
        .arg("-out")
        .arg(&cert)
        .output();
    if !made.as_ref().is_ok_and(|o| o.status.success()) {
        eprintln!("skipped the certificate case: openssl could not make a self-signed certificate here");
        return;
    }
    let server = Nginx::serve_tls(dir.path(), &cert, &key);
    let line = refused_at_once(&format!("https://127.0.0.1:{}/tile.copc.laz", server.port), "a self-signed server");
    assert!(line.contains("certificate"), "{line}");
}

#[test]
fn an_encoded_or_declared_short_body_fails_after_one_request() {
    let file = require!(sample());
    let gzip = BadServer::start(file.clone(), Misbehaviour::Gzip);
    let line = refused_at_once(&gzip.url("tile.copc.laz"), "a gzip body");
    assert!(line.contains("encoded (gzip)"), "{line}");
    assert_eq!(gzip.requests(), 1);
    let short = BadServer::start(file, Misbehaviour::DeclaredShort);
    let line = refused_at_once(&short.url("tile.copc.laz"), "a body declared short");
    assert!(line.contains("Content-Length"), "{line}");
    assert_eq!(short.requests(), 1);
}

#[test]
fn a_connection_cut_in_the_middle_of_a_body_is_still_retried() {
    let file = require!(sample());
    let cut = BadServer::start(file, Misbehaviour::Cut);
    let (output, took) = info(&cut.url("tile.copc.laz"));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success() && stderr.contains("retrying"), "{stderr}");
    assert!(stderr.contains("after 4 retries"), "{stderr}");
    assert_eq!(cut.requests(), 5);
    assert!(took > Duration::from_secs_f64(3.5), "no backoff: {took:?}");
}
