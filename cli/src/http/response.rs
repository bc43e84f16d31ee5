//! An answer, whole in memory, written before a deadline: the status line, the
//! `Content-Type`, `Content-Length`, `Cache-Control: no-store` (a frame or the state is
//! only ever current) and `Connection: close` fields, then the body.

use std::io::{ErrorKind, Write};
use std::net::TcpStream;
use std::time::Instant;

/// Bytes written at a time, each write with the time left to the deadline.
const CHUNK: usize = 64 * 1024;

/// An answer.
#[derive(Debug)]
pub struct Response {
    pub status: u16,
    pub content_type: &'static str,
    pub body: Vec<u8>,
}

impl Response {
    /// A plain-text answer (a refusal's reason).
    pub fn text(status: u16, text: impl Into<String>) -> Response {
        Response { status, content_type: "text/plain; charset=utf-8", body: text.into().into_bytes() }
    }

    /// The status line and the header fields, through the empty line.
    pub fn head(&self) -> String {
        format!(
            "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-store\r\n\
             Connection: close\r\n\r\n",
            self.status,
            reason(self.status),
            self.content_type,
            self.body.len()
        )
    }

    /// Writes the answer to `stream`, failing when the client has not taken it all by
    /// `deadline`.
    pub fn write(&self, stream: &mut TcpStream, deadline: Instant) -> std::io::Result<()> {
        send(stream, self.head().as_bytes(), deadline)?;
        send(stream, &self.body, deadline)?;
        stream.flush()
    }
}

/// Writes `bytes` to `stream` by `deadline`.
fn send(stream: &mut TcpStream, bytes: &[u8], deadline: Instant) -> std::io::Result<()> {
    let mut written = 0;
    while written < bytes.len() {
        let left =
            deadline.checked_duration_since(Instant::now()).filter(|d| !d.is_zero()).ok_or(ErrorKind::TimedOut)?;
        stream.set_write_timeout(Some(left))?;
        match stream.write(&bytes[written..bytes.len().min(written + CHUNK)]) {
            Ok(0) => return Err(ErrorKind::WriteZero.into()),
            Ok(n) => written += n,
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

/// The reason phrase of the statuses the server sends.
fn reason(status: u16) -> &'static str {
    match status {
        200 => "OK",
        400 => "Bad Request",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        413 => "Content Too Large",
        421 => "Misdirected Request",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        501 => "Not Implemented",
        503 => "Service Unavailable",
        505 => "HTTP Version Not Supported",
        507 => "Insufficient Storage",
        _ => "",
    }
}
