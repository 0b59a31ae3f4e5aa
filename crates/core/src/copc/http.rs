//! A file on an HTTP(S) server, read by range requests through `ureq`.
//!
//! `ureq` is a small blocking client with rustls: the loader pool already
//! runs its requests on threads of its own, so an async runtime (`reqwest`
//! with tokio) would add a second scheduler and much more to build for
//! nothing. Opening asks for the first [`MIN_REQUEST`] bytes, which holds the
//! header and the VLRs of every COPC file seen so far and gives the file's
//! length (`Content-Range`); later reads inside them cost no request.
//!
//! Every answer is checked: a server that ignores `Range` (a 200 with the
//! whole file) is refused before its body is read, never downloaded; a 4xx
//! is one line; a 206 whose range or body is shorter than asked is a short
//! read. Timeouts, resets, broken connections and 5xx answers are retried
//! [`HttpOptions::retries`] times, waiting 0.25 s, 0.5 s, 1 s... between; a
//! refused connection, a TLS or certificate failure, an unknown host, a body
//! sent encoded (gzip: its bytes are not the file's) or one the server
//! declares shorter than its range answer the same way every time, so they
//! are refused at once.
//!
//! A URL's user and password are sent (as Basic authorisation) but never
//! shown: [`ByteSource::name`] is the URL with them masked, and caches key on
//! [`ByteSource::identity`], the URL without them.

use std::time::Duration;

use super::CopcError;
use super::redact::{shown, without_credentials};
use super::source::{ByteSource, Counters, check_range};

/// Bytes the first request asks for (the header and VLRs), and the least a
/// merged node request asks for ([`super::load`]).
pub const MIN_REQUEST: u64 = 64 << 10;

/// Timeouts and retries.
#[derive(Debug, Clone)]
pub struct HttpOptions {
    pub connect_timeout: Duration,
    /// The longest wait for an answer, and for the next bytes of a body.
    pub read_timeout: Duration,
    pub retries: u32,
    /// The first wait before a retry; it doubles each time.
    pub backoff: Duration,
}

impl Default for HttpOptions {
    fn default() -> Self {
        Self {
            connect_timeout: Duration::from_secs(10),
            read_timeout: Duration::from_secs(30),
            retries: 4,
            backoff: Duration::from_millis(250),
        }
    }
}

pub struct HttpSource {
    /// The URL as given, credentials included: for requests only, never shown.
    url: String,
    /// The URL as messages show it: its credentials and query values masked.
    name: String,
    /// The URL without its user and password: what caches key on, never shown.
    identity: String,
    agent: ureq::Agent,
    options: HttpOptions,
    len: u64,
    /// The file's first bytes, from the request that opened it.
    prefix: Vec<u8>,
    counters: Counters,
}

/// Why a request failed: worth retrying or not.
enum Failure {
    Retry(String),
    Fatal(String),
}

impl HttpSource {
    /// Asks for the first bytes, which also tells the file's length.
    pub fn open(url: &str, options: &HttpOptions) -> Result<Self, CopcError> {
        let config = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .timeout_connect(Some(options.connect_timeout))
            .timeout_recv_response(Some(options.read_timeout))
            .timeout_recv_body(Some(options.read_timeout))
            .build();
        let mut source = Self {
            url: url.to_string(),
            name: shown(url),
            identity: without_credentials(url),
            agent: config.into(),
            options: options.clone(),
            len: u64::MAX,
            prefix: Vec::new(),
            counters: Counters::default(),
        };
        let (prefix, total) = source.request(0, MIN_REQUEST, true)?;
        source.len = total;
        source.prefix = prefix;
        Ok(source)
    }

    /// Bytes `offset..offset + len` (clipped to the file when `clip`), and the file's length.
    fn request(&self, offset: u64, len: u64, clip: bool) -> Result<(Vec<u8>, u64), CopcError> {
        let mut wait = self.options.backoff;
        let mut attempt = 0;
        loop {
            match self.attempt(offset, len, clip) {
                Ok(answer) => return Ok(answer),
                Err(Failure::Fatal(reason)) => return Err(CopcError::new(&self.name, reason)),
                Err(Failure::Retry(reason)) if attempt >= self.options.retries => {
                    return Err(CopcError::new(
                        &self.name,
                        format!("{reason} (after {} retries)", self.options.retries),
                    ));
                }
                Err(Failure::Retry(reason)) => {
                    let line = format!("{}: {reason}; retrying in {:.2} s", self.name, wait.as_secs_f64());
                    log::warn!("{}", shown(&line));
                    std::thread::sleep(wait);
                    wait *= 2;
                    attempt += 1;
                }
            }
        }
    }

    fn attempt(&self, offset: u64, len: u64, clip: bool) -> Result<(Vec<u8>, u64), Failure> {
        let last = offset + len.max(1) - 1;
        let answer = self
            .agent
            .get(&self.url)
            .header("Range", format!("bytes={offset}-{last}"))
            .header("Accept-Encoding", "identity")
            .call();
        let mut response = answer.map_err(call_failure)?;
        let status = response.status().as_u16();
        match status {
            206 => {}
            200 => {
                return Err(Failure::Fatal(
                    "the server ignores Range requests (it answered 200 with the whole file); streaming needs a server that serves byte ranges".into(),
                ));
            }
            416 => {
                return Err(Failure::Fatal(format!(
                    "bytes {offset}..{} lie past the end of the file (HTTP 416)",
                    offset + len
                )));
            }
            // Not implemented, HTTP version not supported: the same next time.
            501 | 505 => return Err(Failure::Fatal(format!("HTTP {status}"))),
            500..=599 => return Err(Failure::Retry(format!("HTTP {status}"))),
            _ => {
                let reason = response.status().canonical_reason().unwrap_or("");
                return Err(Failure::Fatal(format!("HTTP {status} {reason}").trim_end().to_string()));
            }
        }
        let header =
            |name: &str| response.headers().get(name).and_then(|v| v.to_str().ok()).map(|v| v.trim().to_string());
        // Asked for `identity`: an encoded answer's bytes are not the file's, and asking again gets the same.
        if let Some(encoding) =
            header("content-encoding").filter(|e| !e.is_empty() && !e.eq_ignore_ascii_case("identity"))
        {
            return Err(Failure::Fatal(format!(
                "the server sent the range encoded ({encoding}) though asked for it as is; streaming needs plain byte ranges"
            )));
        }
        let declared: Option<u64> = header("content-length").and_then(|v| v.parse().ok());
        let range = header("content-range");
        let Some((start, end, total)) = range.as_deref().and_then(parse_content_range) else {
            return Err(Failure::Fatal(format!("a 206 answer without a valid Content-Range ({range:?})")));
        };
        let wanted_end = if clip { last.min(total.saturating_sub(1)) } else { last };
        if start != offset || end < wanted_end {
            return Err(Failure::Fatal(format!(
                "asked for bytes {offset}..{}, the server sent {start}..{} of a {total}-byte file (a short read: truncated?)",
                wanted_end + 1,
                end + 1
            )));
        }
        let expected = wanted_end + 1 - offset;
        let body = response.body_mut().with_config().limit(end + 1 - start).read_to_vec();
        let mut body = body.map_err(body_failure)?;
        if (body.len() as u64) < expected {
            let reason = format!("the server sent {} of {expected} bytes", body.len());
            // A body as long as the server said it would be is short on purpose: another try gets the same.
            return Err(if declared == Some(body.len() as u64) {
                Failure::Fatal(format!("{reason} (its Content-Length disagrees with its Content-Range)"))
            } else {
                Failure::Retry(reason)
            });
        }
        body.truncate(expected as usize);
        self.counters.add(expected);
        Ok((body, total))
    }
}

/// A failed call: retried only when another try may answer (a timeout, a
/// connection reset or cut short, a network briefly down); a refused
/// connection, a certificate or TLS failure, an unknown host or a malformed
/// URL answers the same way every time.
fn call_failure(e: ureq::Error) -> Failure {
    let reason = format!("request failed: {e}");
    match &e {
        ureq::Error::Timeout(_) | ureq::Error::BodyStalled | ureq::Error::ConnectionFailed => Failure::Retry(reason),
        ureq::Error::Io(io) if transient(io.kind()) => Failure::Retry(reason),
        _ => Failure::Fatal(reason),
    }
}

/// A body that broke off: retried (the connection went), unless the server
/// sent more than its `Content-Range` says or the bytes cannot be read as sent.
fn body_failure(e: ureq::Error) -> Failure {
    match &e {
        ureq::Error::BodyExceedsLimit(_) => {
            Failure::Fatal(format!("the server sent more bytes than its Content-Range says ({e})"))
        }
        ureq::Error::Io(io) if io.kind() == std::io::ErrorKind::InvalidData => {
            Failure::Fatal(format!("the answer cannot be read: {e}"))
        }
        _ => Failure::Retry(format!("the connection broke while reading: {e}")),
    }
}

/// I/O failures another try may not meet again: the connection or the network went.
fn transient(kind: std::io::ErrorKind) -> bool {
    use std::io::ErrorKind::*;
    matches!(
        kind,
        TimedOut
            | ConnectionReset
            | ConnectionAborted
            | BrokenPipe
            | UnexpectedEof
            | Interrupted
            | WouldBlock
            | NetworkDown
            | NetworkUnreachable
            | HostUnreachable
    )
}

/// `bytes START-END/TOTAL` as numbers.
fn parse_content_range(text: &str) -> Option<(u64, u64, u64)> {
    let rest = text.trim().strip_prefix("bytes")?.trim();
    let (range, total) = rest.split_once('/')?;
    let (start, end) = range.split_once('-')?;
    Some((start.trim().parse().ok()?, end.trim().parse().ok()?, total.trim().parse().ok()?))
}

impl ByteSource for HttpSource {
    fn name(&self) -> &str {
        &self.name
    }
    fn identity(&self) -> &str {
        &self.identity
    }
    fn len(&self) -> u64 {
        self.len
    }
    fn read(&self, offset: u64, len: u64) -> Result<Vec<u8>, CopcError> {
        check_range(&self.name, offset, len, self.len)?;
        if offset + len <= self.prefix.len() as u64 {
            return Ok(self.prefix[offset as usize..(offset + len) as usize].to_vec());
        }
        Ok(self.request(offset, len, false)?.0)
    }
    fn counters(&self) -> &Counters {
        &self.counters
    }
}

#[cfg(test)]
mod tests {
    use super::{Failure, call_failure, parse_content_range};

    #[test]
    fn content_ranges_parse() {
        assert_eq!(parse_content_range("bytes 0-65535/1048576"), Some((0, 65535, 1048576)));
        assert_eq!(parse_content_range("bytes */100"), None);
        assert_eq!(parse_content_range("items 0-1/2"), None);
    }

    #[test]
    fn only_failures_another_try_may_not_meet_are_retried() {
        use std::io::{Error, ErrorKind};
        let retried = |e: ureq::Error| matches!(call_failure(e), Failure::Retry(_));
        for kind in [ErrorKind::TimedOut, ErrorKind::ConnectionReset, ErrorKind::UnexpectedEof] {
            assert!(retried(ureq::Error::Io(Error::new(kind, "x"))), "{kind:?}");
        }
        // Refused, a TLS failure (rustls reports through io as InvalidData), a failed lookup.
        for kind in [ErrorKind::ConnectionRefused, ErrorKind::InvalidData, ErrorKind::Other] {
            assert!(!retried(ureq::Error::Io(Error::new(kind, "x"))), "{kind:?}");
        }
        assert!(!retried(ureq::Error::HostNotFound));
    }
}
