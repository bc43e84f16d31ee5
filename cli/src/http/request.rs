//! A request's head read from a connection within a size and a time: the request line
//! (`METHOD TARGET HTTP/1.x`) and the header fields up to the first empty line, at most
//! [`MAX_HEAD`] bytes in the caller's buffer, arriving before a deadline.
//!
//! Lines end with CRLF, or a bare LF (RFC 9112, section 2.2, lets a recipient accept
//! it). Of the fields, only `Host`, `Content-Length` and `Transfer-Encoding` are kept:
//! the body they announce is refused or left unread (the module above says which), so
//! a declared length is only ever compared, never allocated.

use std::io::{ErrorKind, Read};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use super::{MAX_BODY, MAX_HEAD, Response};

/// The wait of the read made once the deadline has passed.
const LAST_READ: Duration = Duration::from_millis(1);

/// A request as the handler sees it.
#[derive(Debug)]
pub struct Request {
    /// `GET`, `POST`, ... as sent (methods are case-sensitive).
    pub method: String,
    /// The request target: a path and its query (`/frame?size=64x48`).
    pub target: String,
    /// The `Host` field, if any.
    pub host: Option<String>,
    /// An HTTP/1.0 request (which may leave out `Host`).
    pub http_1_0: bool,
}

impl Request {
    /// The target's path and query (empty without a `?`).
    pub fn path_and_query(&self) -> (&str, &str) {
        self.target.split_once('?').unwrap_or((&self.target, ""))
    }
}

/// A request head, and whether the client may have sent bytes the server will not read
/// (a body, or more requests).
pub struct Head {
    pub request: Request,
    pub unread: bool,
}

/// Why no request is handled.
pub enum Failure {
    /// The client closed the connection or failed before sending a whole head: nothing
    /// to answer.
    Gone,
    /// Answered with this (a `4xx` or `5xx`) and closed.
    Refused(Response),
}

/// Reads a request head from `stream` into `buffer` (at least [`MAX_HEAD`] bytes) by
/// `deadline`.
pub fn read_head(stream: &mut TcpStream, buffer: &mut [u8], deadline: Instant) -> Result<Head, Failure> {
    let buffer = &mut buffer[..MAX_HEAD];
    let late = || Failure::Refused(Response::text(408, "the request's head did not arrive in time\n"));
    let (mut filled, mut last_read) = (0, false);
    let end = loop {
        if let Some(end) = head_end(&buffer[..filled]) {
            break end;
        }
        if filled == buffer.len() {
            return Err(Failure::Refused(Response::text(
                431,
                format!("the request's head is longer than {MAX_HEAD} bytes\n"),
            )));
        }
        if last_read {
            return Err(late());
        }
        // Past the deadline, one last short read: a connection that waited in the queue
        // may have its whole head ready.
        let left = deadline.saturating_duration_since(Instant::now());
        last_read = left.is_zero();
        stream.set_read_timeout(Some(left.max(LAST_READ))).map_err(|_| Failure::Gone)?;
        match stream.read(&mut buffer[filled..]) {
            Ok(0) => return Err(Failure::Gone),
            Ok(n) => filled += n,
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => return Err(late()),
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(_) => return Err(Failure::Gone),
        }
    };
    let request = parse(&buffer[..end]).map_err(Failure::Refused)?;
    Ok(Head { unread: request.1 || filled > end, request: request.0 })
}

/// The length of the head at the start of `bytes` (through its empty line), if whole.
fn head_end(bytes: &[u8]) -> Option<usize> {
    let mut line_start = 0;
    for (i, &b) in bytes.iter().enumerate() {
        if b == b'\n' {
            let line = &bytes[line_start..i];
            if (line.is_empty() || line == b"\r") && line_start > 0 {
                return Some(i + 1);
            }
            line_start = i + 1;
        }
    }
    None
}

/// The request in a whole head, and whether it declares a body.
fn parse(head: &[u8]) -> Result<(Request, bool), Response> {
    let bad = |why: &str| Response::text(400, format!("bad request: {why}\n"));
    let head = std::str::from_utf8(head).map_err(|_| bad("the head is not UTF-8"))?;
    let mut lines = head.split('\n').map(|l| l.strip_suffix('\r').unwrap_or(l));
    let request_line = lines.next().unwrap_or_default();
    let mut parts = request_line.split(' ');
    let (Some(method), Some(target), Some(version), None) = (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return Err(bad("the request line is not METHOD TARGET VERSION"));
    };
    if method.is_empty() || !method.bytes().all(is_token) {
        return Err(bad("the method is not a token"));
    }
    if !target.starts_with('/') || !target.bytes().all(|b| b.is_ascii_graphic()) {
        return Err(bad("the target is not a path"));
    }
    let http_1_0 = match version {
        "HTTP/1.1" => false,
        "HTTP/1.0" => true,
        v if v.starts_with("HTTP/") => {
            return Err(Response::text(505, "only HTTP/1.0 and HTTP/1.1 are served\n"));
        }
        _ => return Err(bad("the version is not HTTP/1.x")),
    };
    let (mut host, mut length, mut body) = (None::<String>, None::<u64>, false);
    for line in lines.take_while(|l| !l.is_empty()) {
        if line.starts_with([' ', '\t']) {
            return Err(bad("folded header lines are obsolete"));
        }
        let (name, value) = line.split_once(':').ok_or_else(|| bad("a header line without ':'"))?;
        if name.is_empty() || !name.bytes().all(is_token) {
            return Err(bad("a header name is not a token"));
        }
        let value = value.trim_matches([' ', '\t']);
        if name.eq_ignore_ascii_case("host") {
            if host.replace(value.to_string()).is_some() {
                return Err(bad("more than one Host"));
            }
        } else if name.eq_ignore_ascii_case("transfer-encoding") {
            return Err(Response::text(501, "Transfer-Encoding is not served (no request takes a body)\n"));
        } else if name.eq_ignore_ascii_case("content-length") {
            // Digits only, compared without overflow: 20 digits or more are above any limit.
            if value.is_empty() || !value.bytes().all(|b| b.is_ascii_digit()) {
                return Err(bad("Content-Length is not a number"));
            }
            let declared = value.parse::<u64>().unwrap_or(u64::MAX);
            if length.replace(declared).is_some_and(|l| l != declared) {
                return Err(bad("two different Content-Lengths"));
            }
            if declared > MAX_BODY {
                return Err(Response::text(413, format!("a body of at most {MAX_BODY} bytes (none is read)\n")));
            }
            body |= declared > 0;
        }
    }
    if host.is_none() && !http_1_0 {
        return Err(bad("an HTTP/1.1 request without Host"));
    }
    Ok((Request { method: method.into(), target: target.into(), host, http_1_0 }, body))
}

/// A byte of an HTTP token (RFC 9110, section 5.6.2).
fn is_token(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b"!#$%&'*+-.^_`|~".contains(&b)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(head: &str) -> u16 {
        match parse(head.as_bytes()) {
            Ok(_) => 200,
            Err(response) => response.status,
        }
    }

    #[test]
    fn heads_end_at_the_first_empty_line() {
        assert_eq!(head_end(b"GET / HTTP/1.0\r\n\r\nrest"), Some(18));
        assert_eq!(head_end(b"GET / HTTP/1.0\n\nrest"), Some(16));
        assert_eq!(head_end(b"GET / HTTP/1.0\r\nHost: a\r\n"), None);
        assert_eq!(head_end(b"\r\n"), None, "a request line, not an empty head");
    }

    #[test]
    fn requests_are_refused_with_the_status_that_says_why() {
        assert_eq!(status("GET /state HTTP/1.1\r\nHost: localhost\r\n"), 200);
        assert_eq!(status("GET /state HTTP/1.0\r\n"), 200);
        assert_eq!(status("GET /state HTTP/1.1\r\n"), 400, "HTTP/1.1 needs a Host");
        assert_eq!(status("GET /state HTTP/2.0\r\nHost: a\r\n"), 505);
        assert_eq!(status("GET  /state HTTP/1.0\r\n"), 400);
        assert_eq!(status("GET http://a/ HTTP/1.0\r\n"), 400);
        assert_eq!(status("GET / HTTP/1.0\r\nContent-Length: 65536\r\n"), 200);
        assert_eq!(status("GET / HTTP/1.0\r\nContent-Length: 65537\r\n"), 413);
        assert_eq!(status("GET / HTTP/1.0\r\nContent-Length: 99999999999999999999999\r\n"), 413);
        assert_eq!(status("GET / HTTP/1.0\r\nContent-Length: -1\r\n"), 400);
        assert_eq!(status("GET / HTTP/1.0\r\nContent-Length: 5\r\nContent-Length: 6\r\n"), 400);
        assert_eq!(status("GET / HTTP/1.0\r\nTransfer-Encoding: chunked\r\n"), 501);
        assert_eq!(status("GET / HTTP/1.0\r\nHost: a\r\nHost: b\r\n"), 400);
        assert_eq!(status("GET / HTTP/1.0\r\nX: a\r\n b\r\n"), 400);
        assert_eq!(status("GET / HTTP/1.0\r\nX a\r\n"), 400);
    }
}
