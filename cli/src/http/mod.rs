//! A small HTTP/1.1 server for the viewer: `GET` requests without bodies, one request a
//! connection, every answer in memory before it is sent.
//!
//! What it promises, whatever a client on the machine sends (a client may stall, flood,
//! lie about lengths or never read):
//! - it keeps answering: no request makes it exit, abort or stop serving the others,
//!   and the memory a connection costs is bounded before anything is read;
//! - a connection holds a worker for at most what is left of [`HEAD_DEADLINE`] to
//!   send its request, the handler's time, [`WRITE_DEADLINE`] to take the answer and
//!   [`LINGER`] after it;
//! - it answers only hosts of this machine ([`host`]): a web page that rebinds its own
//!   name to 127.0.0.1 cannot read what the server says.
//!
//! How (the limits, and why each):
//! - One thread accepts; [`WORKERS`] threads, started before the first connection,
//!   read requests and answer them. No thread is started afterwards, so running out of
//!   threads cannot stop a running server. The accepting thread hands each connection
//!   to the workers through a queue of [`QUEUED`]; a connection beyond that is answered
//!   `503` at once and closed, so a flood costs the workers nothing.
//! - A request's head (request line and headers) is at most [`MAX_HEAD`] bytes
//!   (`431`), in a buffer of that size a worker allocates once, and must arrive within
//!   [`HEAD_DEADLINE`] of the connection being accepted (`408`): a slow or endless head
//!   costs a bounded buffer and a bounded time, and connections that waited in the
//!   queue past their deadline are answered at once (a head already there is still
//!   read), so a flood of silent connections is cleared within one deadline.
//! - A body is never read (no route takes one) and no length a client declares is ever
//!   allocated: a `Content-Length` above [`MAX_BODY`] is a `413`, `Transfer-Encoding` a
//!   `501` (the only coding HTTP/1.1 needs is chunked, which no route takes). A smaller
//!   declared body is ignored: the request is answered and the connection closed.
//! - Every answer says `Connection: close` and the connection is closed after it: a
//!   browser's idle keep-alive connection would otherwise hold a worker, and pipelined
//!   requests beyond the first are never read. Before closing a connection with bytes
//!   still unread (a body, pipelined requests), the server stops writing and reads and
//!   discards for at most [`LINGER`] or [`LINGER_BYTES`], so the client sees the answer
//!   rather than a reset.
//! - An answer must be taken within [`WRITE_DEADLINE`], or the connection is dropped: a
//!   client that never reads holds a worker that long, not for ever.
//! - An error accepting a connection (out of file descriptors, `EMFILE`) is reported
//!   on stderr at most once every [`ACCEPT_REPORT_EVERY`] and accepting is retried every
//!   [`ACCEPT_RETRY`]: the server waits for descriptors to be freed rather than exit.
//! - A handler that panics answers `500`; its worker goes on.
//!
//! Where it departs from HTTP/1.1 (RFC 9110, 9112): no keep-alive, no bodies, no
//! `Expect: 100-continue` (a client waiting for it gets the answer instead), obsolete
//! line folding and non-UTF-8 heads are `400`; a request without `Host` is served for
//! HTTP/1.0 only (HTTP/1.1 requires it).

mod host;
mod request;
mod response;

use std::io::{ErrorKind, Write};
use std::net::{IpAddr, Shutdown, SocketAddr, TcpListener, TcpStream};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::mpsc::{Receiver, TrySendError, sync_channel};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow};

pub use request::Request;
pub use response::Response;

use request::Head;

/// Threads reading requests and answering them.
pub const WORKERS: usize = 8;
/// Connections waiting for a worker; more are answered `503`.
pub const QUEUED: usize = 56;
/// Longest request head (request line and headers), in bytes.
pub const MAX_HEAD: usize = 16 * 1024;
/// Time a client has to send its request head, from its connection being accepted.
pub const HEAD_DEADLINE: Duration = Duration::from_secs(10);
/// Largest body a request may declare (it is not read).
pub const MAX_BODY: u64 = 64 * 1024;
/// Time a client has to take an answer.
pub const WRITE_DEADLINE: Duration = Duration::from_secs(30);
/// Longest wait for a client's unread bytes before closing its connection.
pub const LINGER: Duration = Duration::from_secs(1);
/// Most unread bytes read and discarded before closing a connection.
pub const LINGER_BYTES: usize = 1 << 20;
/// Pause before accepting again after an error.
pub const ACCEPT_RETRY: Duration = Duration::from_millis(100);
/// Least time between two reports of accept errors.
pub const ACCEPT_REPORT_EVERY: Duration = Duration::from_secs(60);

/// A listening server, not yet serving.
pub struct Server {
    listener: TcpListener,
    address: SocketAddr,
}

impl Server {
    /// Listens on `address` (port 0: a free one).
    pub fn bind(address: SocketAddr) -> Result<Server> {
        let listener = TcpListener::bind(address).with_context(|| format!("cannot listen on {address}"))?;
        let address = listener.local_addr().context("the server has no address")?;
        Ok(Server { listener, address })
    }

    /// The address it listens on.
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// Answers every request by `handler`, for ever; fails only when the workers cannot
    /// be started.
    pub fn serve(self, handler: impl Fn(&Request) -> Response + Send + Sync + 'static) -> Result<()> {
        let (queue, waiting) = sync_channel::<(TcpStream, Instant)>(QUEUED);
        let waiting = Arc::new(Mutex::new(waiting));
        let handler = Arc::new(handler);
        for n in 0..WORKERS {
            let (waiting, handler) = (Arc::clone(&waiting), Arc::clone(&handler));
            let bound = self.address.ip();
            std::thread::Builder::new()
                .name(format!("http-{n}"))
                .spawn(move || work(&waiting, &*handler, bound))
                .context("cannot start the server's threads")?;
        }
        let mut last_report: Option<Instant> = None;
        loop {
            match self.listener.accept() {
                Ok((stream, _)) => match queue.try_send((stream, Instant::now())) {
                    Ok(()) => {}
                    Err(TrySendError::Full((stream, _))) => refuse_at_once(stream),
                    Err(TrySendError::Disconnected(_)) => return Err(anyhow!("the server's threads are gone")),
                },
                // The client gave up before it was accepted: nothing to wait for.
                Err(e) if matches!(e.kind(), ErrorKind::ConnectionAborted | ErrorKind::Interrupted) => {}
                Err(e) => {
                    if last_report.is_none_or(|t| t.elapsed() >= ACCEPT_REPORT_EVERY) {
                        warn!("cannot accept a connection ({e}); retrying every {} ms", ACCEPT_RETRY.as_millis());
                        last_report = Some(Instant::now());
                    }
                    std::thread::sleep(ACCEPT_RETRY);
                }
            }
        }
    }
}

/// A worker: takes connections from the queue and answers each.
fn work(
    waiting: &Mutex<Receiver<(TcpStream, Instant)>>,
    handler: &(dyn Fn(&Request) -> Response + Sync),
    bound: IpAddr,
) {
    let mut buffer = vec![0; MAX_HEAD];
    loop {
        let next = waiting.lock().unwrap_or_else(PoisonError::into_inner).recv();
        let Ok((stream, accepted)) = next else { return };
        connection(stream, accepted + HEAD_DEADLINE, &mut buffer, handler, bound);
    }
}

/// Reads one request from `stream`, answers it and closes the connection.
fn connection(
    mut stream: TcpStream,
    head_deadline: Instant,
    buffer: &mut [u8],
    handler: &(dyn Fn(&Request) -> Response + Sync),
    bound: IpAddr,
) {
    let local = stream.local_addr().map(|a| a.ip()).ok();
    let head = match request::read_head(&mut stream, buffer, head_deadline) {
        Ok(head) => head,
        Err(request::Failure::Gone) => return,
        Err(request::Failure::Refused(response)) => {
            let _ = response.write(&mut stream, Instant::now() + WRITE_DEADLINE);
            // A head refused when whole or too long may be followed by more; a late one
            // has been read to its last byte.
            close(stream, response.status != 408);
            return;
        }
    };
    let Head { request, unread } = head;
    let response = if !host::allowed(request.host.as_deref(), request.http_1_0, bound, local) {
        Response::text(421, "this server answers only requests to this machine's own addresses (Host)\n")
    } else {
        catch_unwind(AssertUnwindSafe(|| handler(&request)))
            .unwrap_or_else(|_| Response::text(500, "the server failed answering this request\n"))
    };
    let _ = response.write(&mut stream, Instant::now() + WRITE_DEADLINE);
    close(stream, unread);
}

/// Answers `503` on the accepting thread and closes the connection: the answer is
/// small enough for the socket's buffer, so this does not wait for the client.
fn refuse_at_once(mut stream: TcpStream) {
    let response = Response::text(503, "the server is busy; try again\n");
    let _ = stream.set_write_timeout(Some(Duration::from_millis(100)));
    let _ = stream.write_all(&[response.head().as_bytes(), &response.body].concat());
    let _ = stream.shutdown(Shutdown::Write);
}

/// Closes a connection; when the client may have sent bytes not read (`unread`), stops
/// writing first and discards what it sends for a bounded time, so that closing with
/// data unread does not reset the connection before the client reads the answer.
fn close(mut stream: TcpStream, unread: bool) {
    if !unread || stream.shutdown(Shutdown::Write).is_err() {
        return;
    }
    let deadline = Instant::now() + LINGER;
    let mut scratch = [0; 8192];
    let mut discarded = 0;
    while discarded < LINGER_BYTES {
        let Some(left) = deadline.checked_duration_since(Instant::now()).filter(|d| !d.is_zero()) else { return };
        if stream.set_read_timeout(Some(left)).is_err() {
            return;
        }
        match std::io::Read::read(&mut stream, &mut scratch) {
            Ok(0) | Err(_) => return,
            Ok(n) => discarded += n,
        }
    }
}
