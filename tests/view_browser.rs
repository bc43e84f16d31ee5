//! `octsolid view` in a real browser: Debian's Chromium, headless, driven over the
//! DevTools protocol. The page loads and shows a frame; a mouse drag orbits the view,
//! and the picture it then shows is byte for byte the frame the server renders for the
//! page's new camera; the section slider cuts the solid; a screenshot is saved
//! (target/view-browser.png).
//!
//! Needs `chromium`, so the test is ignored by a plain `cargo test` (the summary says
//! so) and run by `.ci/run`, which installs it first (`cargo test --
//! --include-ignored`); run so without chromium, it fails.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use tungstenite::{Message, WebSocket, stream::MaybeTlsStream};

mod common;

/// A child process killed when dropped.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn scratch() -> PathBuf {
    common::scratch_dir("view-browser", "pages")
}

/// One HTTP/1.0 GET of the viewer (which then neither chunks nor keeps the connection).
fn get(address: &str, target: &str) -> (u16, Vec<u8>) {
    get_as(address, target, "HTTP/1.0")
}

/// One HTTP GET: the status and body, read to its Content-Length where it has one
/// (the DevTools server speaks HTTP/1.1 only and keeps the connection open).
fn get_as(address: &str, target: &str, version: &str) -> (u16, Vec<u8>) {
    let stream = TcpStream::connect(address).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(120))).unwrap();
    write!(&stream, "GET {target} {version}\r\nHost: {address}\r\nConnection: close\r\n\r\n").unwrap();
    let mut reader = BufReader::new(stream);
    let (mut status, mut length) = (0, None);
    loop {
        let mut line = String::new();
        reader.read_line(&mut line).unwrap();
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if line.starts_with("HTTP/") {
            status = line.split(' ').nth(1).unwrap().parse().unwrap();
        } else if let Some((_, value)) = line.split_once(':').filter(|(n, _)| n.eq_ignore_ascii_case("content-length"))
        {
            length = Some(value.trim().parse::<usize>().unwrap());
        }
    }
    let mut body = Vec::new();
    match length {
        Some(n) => {
            body.resize(n, 0);
            reader.read_exact(&mut body).unwrap();
        }
        None => {
            reader.read_to_end(&mut body).unwrap();
        }
    }
    (status, body)
}

/// The DevTools protocol over one page's WebSocket.
struct Page {
    socket: WebSocket<MaybeTlsStream<TcpStream>>,
    next_id: u64,
}

impl Page {
    fn call(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        self.socket.send(Message::text(json!({"id": id, "method": method, "params": params}).to_string())).unwrap();
        loop {
            let Message::Text(text) = self.socket.read().unwrap() else { continue };
            let reply: Value = serde_json::from_str(&text).unwrap();
            if reply["id"].as_u64() == Some(id) {
                assert!(reply["error"].is_null(), "{method}: {reply}");
                return reply["result"].clone();
            }
        }
    }

    /// The value of a JavaScript expression (promises awaited).
    fn eval(&mut self, expression: &str) -> Value {
        let result = self
            .call("Runtime.evaluate", json!({"expression": expression, "awaitPromise": true, "returnByValue": true}));
        assert!(result["exceptionDetails"].is_null(), "{expression}: {result}");
        result["result"]["value"].clone()
    }

    /// Waits until the expression is truthy.
    fn wait_for(&mut self, expression: &str) -> Value {
        let started = Instant::now();
        loop {
            let value = self.eval(expression);
            if !(value.is_null() || value == json!(false) || value == json!("")) {
                return value;
            }
            assert!(started.elapsed() < Duration::from_secs(90), "waited in vain for {expression}");
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// The still frame the page shows once the view rests: its query and bytes.
    fn still(&mut self, not: &str) -> (String, Vec<u8>) {
        let query = self
            .wait_for(&format!(
                "(() => {{ const q = document.getElementById('frame')?.dataset.query || ''; \
                 return q.includes('spp=2') && q !== {not:?} ? q : ''; }})()"
            ))
            .as_str()
            .unwrap()
            .to_string();
        let bytes = self.eval(
            "fetch(document.getElementById('frame').src).then(r => r.arrayBuffer()).then(b => Array.from(new Uint8Array(b)))",
        );
        (query, bytes.as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as u8).collect())
    }

    fn mouse(&mut self, kind: &str, x: f64, y: f64) {
        let buttons = if kind == "mouseReleased" { 0 } else { 1 };
        self.call(
            "Input.dispatchMouseEvent",
            json!({"type": kind, "x": x, "y": y, "button": "left", "buttons": buttons, "clickCount": 1}),
        );
    }
}

fn browser() -> Option<PathBuf> {
    ["/usr/bin/chromium", "/usr/bin/chromium-browser"].iter().map(PathBuf::from).find(|p| p.exists())
}

#[test]
#[ignore = "needs chromium: tests/data/install_reference_tools.sh, then cargo test -- --include-ignored (.ci/run does)"]
fn a_browser_orbits_and_sections_and_sees_the_servers_frames() {
    let chromium = browser().expect("chromium is missing: tests/data/install_reference_tools.sh installs it");
    let dir = scratch();
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_octsolid")).current_dir(&dir).args(args).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    };
    run(&["shape", "torus", "--depth", "7", "-o", "ring.oct"]);
    let mut viewer = Killed(
        Command::new(env!("CARGO_BIN_EXE_octsolid"))
            .current_dir(&dir)
            .args(["view", "ring.oct"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let mut line = String::new();
    BufReader::new(viewer.0.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let address = line.split("http://").nth(1).and_then(|s| s.split('/').next()).unwrap().to_string();

    let profile = dir.join("profile");
    let mut chrome = Killed(
        Command::new(chromium)
            .args(["--headless", "--no-sandbox", "--disable-gpu", "--remote-debugging-port=0"])
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg("--window-size=900,700")
            .arg(format!("http://{address}/"))
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    // "DevTools listening on ws://127.0.0.1:PORT/devtools/browser/ID"; the rest of its
    // stderr is drained so that the browser never blocks on it.
    let stderr = BufReader::new(chrome.0.stderr.take().unwrap());
    let (found, address_of_devtools) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in stderr.lines().map_while(Result::ok) {
            if let Some(rest) = line.split("ws://").nth(1) {
                let _ = found.send(rest.split('/').next().unwrap_or_default().to_string());
            }
        }
    });
    let devtools =
        address_of_devtools.recv_timeout(Duration::from_secs(60)).expect("chromium prints its DevTools address");
    let targets: Value = {
        let started = Instant::now();
        loop {
            let list: Value = serde_json::from_slice(&get_as(&devtools, "/json/list", "HTTP/1.1").1).unwrap();
            if list.as_array().is_some_and(|l| l.iter().any(|t| t["type"] == "page")) {
                break list;
            }
            assert!(started.elapsed() < Duration::from_secs(30), "no page: {list}");
            std::thread::sleep(Duration::from_millis(100));
        }
    };
    let page = targets.as_array().unwrap().iter().find(|t| t["type"] == "page").unwrap();
    let (socket, _) = tungstenite::connect(page["webSocketDebuggerUrl"].as_str().unwrap()).unwrap();
    let mut page = Page { socket, next_id: 0 };

    // The first still frame, as the server renders it for the page's camera.
    let (first_query, first) = page.still("");
    assert!(first == get(&address, &format!("/frame?{first_query}")).1, "the page shows the server's frame");

    // Drag to orbit: the view turns, and the still it rests on is the server's frame.
    page.mouse("mousePressed", 450.0, 330.0);
    for step in 1..=10 {
        page.mouse("mouseMoved", 450.0 + 8.0 * f64::from(step), 330.0 + 2.0 * f64::from(step));
    }
    page.mouse("mouseReleased", 530.0, 350.0);
    let (orbited_query, orbited) = page.still(&first_query);
    let eye = |q: &str| q.split('&').find(|p| p.starts_with("eye=")).unwrap().to_string();
    assert_ne!(eye(&orbited_query), eye(&first_query), "the drag moved the eye");
    assert!(orbited != first, "the picture changed");
    assert!(orbited == get(&address, &format!("/frame?{orbited_query}")).1, "the orbited view is the server's");

    // The section: an axis, then the slider.
    page.eval(
        "(() => { const a = document.getElementById('axis'); a.value = 'z'; \
         a.dispatchEvent(new Event('change')); const c = document.getElementById('cut'); c.value = 400; \
         c.dispatchEvent(new Event('input')); return true; })()",
    );
    let (cut_query, cut) = page.still(&orbited_query);
    assert!(cut_query.contains("section=z,"), "{cut_query}");
    assert!(cut != orbited, "the section changed the picture");
    assert!(cut == get(&address, &format!("/frame?{cut_query}")).1, "the section view is the server's");

    let shot = page.call("Page.captureScreenshot", json!({"format": "png"}));
    let png = decode_base64(shot["data"].as_str().unwrap());
    assert_eq!(&png[1..4], b"PNG");
    let target = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/view-browser.png");
    std::fs::write(target, png).unwrap();
    drop(page);
    drop(chrome);
    drop(viewer);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Standard base64 (the screenshot's encoding).
fn decode_base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let digits: Vec<u8> = text.bytes().filter(|&c| c != b'=').map(value).collect();
    digits
        .chunks(4)
        .flat_map(|c| {
            let n = c.iter().enumerate().fold(0u32, |n, (i, &d)| n | u32::from(d) << (18 - 6 * i));
            let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
            bytes.into_iter().take(c.len() - 1)
        })
        .collect()
}
