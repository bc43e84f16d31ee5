//! Which `Host` a request may name: this machine's, so that DNS rebinding cannot read
//! the server's answers.
//!
//! A web page may point its own name at 127.0.0.1 and then ask the server for
//! `/state`: the browser treats the answer as the page's own and lets it read it. Such a
//! request names the page's host in `Host`, so the server answers only these hosts,
//! with or without a port: `localhost`, a loopback address (`127.0.0.1`, `[::1]`), the
//! address the server is bound to, and the address the client connected to (which
//! differs from the bound one when that is `0.0.0.0` or `::`). An address written as
//! an address is never a rebound name. A request without `Host` is HTTP/1.0 (the
//! request parser refuses the others), which no browser sends.

use std::net::{IpAddr, Ipv6Addr};

/// Whether a request naming `host` (`None`: no `Host` field, HTTP/1.0 only) may be
/// answered by a server bound to `bound`, on a connection to `local`.
pub fn allowed(host: Option<&str>, http_1_0: bool, bound: IpAddr, local: Option<IpAddr>) -> bool {
    let Some(host) = host else { return http_1_0 };
    let Some(name) = without_port(host) else { return false };
    if name.eq_ignore_ascii_case("localhost") {
        return true;
    }
    let address = match name.strip_prefix('[').and_then(|n| n.strip_suffix(']')) {
        Some(v6) => v6.parse::<Ipv6Addr>().map(IpAddr::V6),
        None => name.parse::<std::net::Ipv4Addr>().map(IpAddr::V4),
    };
    address.is_ok_and(|a| a.is_loopback() || (!a.is_unspecified() && (a == bound || Some(a) == local)))
}

/// `host` without its `:PORT`, if any; `None` when the port is not a port.
fn without_port(host: &str) -> Option<&str> {
    let split = match host.rfind(':') {
        // A colon inside brackets is an IPv6 address's.
        Some(i) if !host[i..].contains(']') => i,
        _ => return Some(host),
    };
    let (name, port) = (&host[..split], &host[split + 1..]);
    (port.len() <= 5 && port.bytes().all(|b| b.is_ascii_digit()) && port.parse::<u16>().is_ok()).then_some(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    const LOOPBACK: IpAddr = IpAddr::V4(std::net::Ipv4Addr::LOCALHOST);

    fn ok(host: &str) -> bool {
        allowed(Some(host), false, LOOPBACK, Some(LOOPBACK))
    }

    #[test]
    fn this_machines_hosts_are_answered_with_or_without_a_port() {
        for host in ["127.0.0.1", "127.0.0.1:8080", "localhost", "LocalHost:1", "[::1]", "[::1]:65535", "127.0.0.2"] {
            assert!(ok(host), "{host}");
        }
        let (bound, local) = ("192.168.1.7".parse().unwrap(), "10.0.0.3".parse().unwrap());
        assert!(allowed(Some("192.168.1.7:80"), false, bound, Some(local)));
        assert!(allowed(Some("10.0.0.3"), false, "0.0.0.0".parse().unwrap(), Some(local)));
        assert!(allowed(None, true, LOOPBACK, None), "HTTP/1.0 may leave Host out");
    }

    #[test]
    fn other_hosts_are_not() {
        for host in [
            "evil.example",
            "evil.example:8080",
            "localhost.evil.example",
            "127.0.0.1.evil.example",
            "0.0.0.0",
            "[::]",
            "192.168.1.7",
            "127.0.0.1:99999",
            "127.0.0.1:",
            "[::1",
            "::1",
            "",
        ] {
            assert!(!ok(host), "{host}");
        }
        assert!(!allowed(None, false, LOOPBACK, None), "HTTP/1.1 must name its host");
    }
}
