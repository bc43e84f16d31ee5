//! `octsolid view`: the server's frames against `octsolid render`'s files for the same
//! flags, byte for byte; bad requests refused with 4xx while the server goes on; live
//! reload under `--watch`, a scene with an error keeping the last good picture; hostile
//! clients on real sockets (a huge declared length, a body never sent, a slow head, a
//! stalled reader, an endless header, a flood, a foreign Host, no file descriptors
//! left), after each of which an ordinary request is still answered; frames within
//! `--memory-budget`.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

mod common;

/// A scratch folder of its own, removed when dropped.
struct Scratch(std::path::PathBuf);

impl Scratch {
    fn new() -> Scratch {
        static NEXT: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        Scratch(common::scratch_dir("view", &n.to_string()))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A running `octsolid view`, killed when dropped.
struct Viewer {
    child: Child,
    address: String,
    _stdout: BufReader<ChildStdout>,
}

impl Drop for Viewer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn octsolid(dir: &Path, args: &[&str]) -> std::process::Output {
    let out = Command::new(env!("CARGO_BIN_EXE_octsolid")).current_dir(dir).args(args).output().unwrap();
    assert!(out.status.success(), "octsolid {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    out
}

/// Starts `octsolid view ARGS` and reads the address it prints.
fn view(dir: &Path, args: &[&str]) -> Viewer {
    let mut command = Command::new(env!("CARGO_BIN_EXE_octsolid"));
    command.arg("view").args(args);
    start(dir, command)
}

/// Starts a viewer by `command` and reads the address it prints.
fn start(dir: &Path, mut command: Command) -> Viewer {
    let mut child = command.current_dir(dir).stdout(Stdio::piped()).stderr(Stdio::null()).spawn().unwrap();
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    stdout.read_line(&mut line).unwrap();
    let address = line.split("http://").nth(1).and_then(|s| s.split('/').next()).unwrap_or_default().to_string();
    assert!(address.starts_with("127.0.0.1:"), "binds the loopback address by default: {line}");
    Viewer { child, address, _stdout: stdout }
}

/// One HTTP request: the status and the body.
fn request(address: &str, method: &str, target: &str) -> (u16, Vec<u8>) {
    let mut stream = TcpStream::connect(address).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(120))).unwrap();
    write!(stream, "{method} {target} HTTP/1.0\r\nHost: {address}\r\n\r\n").unwrap();
    let mut response = Vec::new();
    stream.read_to_end(&mut response).unwrap();
    let split = response.windows(4).position(|w| w == b"\r\n\r\n").expect("a header") + 4;
    let head = String::from_utf8_lossy(&response[..split]).to_string();
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, response[split..].to_vec())
}

fn get(address: &str, target: &str) -> (u16, Vec<u8>) {
    request(address, "GET", target)
}

#[test]
fn frames_are_the_files_render_writes() {
    let dir = Scratch::new();
    let d = dir.0.as_path();
    octsolid(d, &["shape", "torus", "--depth", "6", "-o", "ring.oct"]);
    let viewer = view(d, &["ring.oct"]);
    let (status, page) = get(&viewer.address, "/");
    assert_eq!(status, 200);
    assert!(String::from_utf8_lossy(&page).contains("/frame?"), "the page asks for frames");
    let cameras = [
        "eye=3,-2,1.5&target=0,0,0&up=z&fov=30&size=96x64&spp=1",
        "eye=0.5,-3,2&target=0.1,0,0&up=z&fov=40&size=80x80&spp=2&normals=axis&no-shadows=1",
        "eye=-2,-2,2&target=0,0,0&up=z&fov=35&size=120x90&spp=1&method=front-to-back&ortho=1",
        "view=top&size=64x48&spp=1",
        "eye=2,3,2&target=0,0,0&up=z&fov=35&size=72x54&spp=1&section=y,0.1",
        "eye=2,3,2&target=0,0,0&up=z&fov=35&size=72x54&spp=1&section=x,-0.2&method=front-to-back",
    ];
    for (i, query) in cameras.iter().enumerate() {
        let (status, frame) = get(&viewer.address, &format!("/frame?{query}"));
        assert_eq!(status, 200, "{query}: {}", String::from_utf8_lossy(&frame));
        let mut args = vec!["render".to_string(), "ring.oct".into(), "-o".into(), format!("r{i}.png")];
        for pair in query.split('&') {
            let (key, value) = pair.split_once('=').unwrap();
            args.push(if ["no-shadows", "ortho"].contains(&key) {
                format!("--{key}")
            } else {
                format!("--{key}={value}")
            });
        }
        octsolid(d, &args.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(frame == std::fs::read(d.join(format!("r{i}.png"))).unwrap(), "{query}: the frame differs");
    }
    // A section view shows less of the solid than the whole (and is not the whole).
    let whole = get(&viewer.address, "/frame?eye=2,3,2&target=0,0,0&up=z&fov=35&size=72x54&spp=1").1;
    let cut = get(&viewer.address, "/frame?eye=2,3,2&target=0,0,0&up=z&fov=35&size=72x54&spp=1&section=y,0.1").1;
    assert!(whole != cut, "the section changes the picture");
    // The camera endpoint gives the camera of a named view, which renders the same.
    let (status, camera) = get(&viewer.address, "/camera?view=front&size=64x48");
    assert_eq!(status, 200);
    let camera: serde_json::Value = serde_json::from_slice(&camera).unwrap();
    assert!(camera["eye"][1].as_f64().unwrap() < 0.0, "front looks from -y: {camera}");
}

#[test]
fn bad_requests_get_4xx_and_the_server_goes_on() {
    let dir = Scratch::new();
    let d = dir.0.as_path();
    octsolid(d, &["shape", "sphere", "--depth", "5", "-o", "ball.oct"]);
    let viewer = view(d, &["ball.oct"]);
    let a = &viewer.address;
    let long = format!("/frame?eye={}", "1".repeat(3000));
    let refused = [
        ("GET", "/ball.oct"),
        ("GET", "/../ball.oct"),
        ("GET", "/%2e%2e/ball.oct"),
        ("GET", "/frame?eye=nan,1,1"),
        ("GET", "/frame?eye=1,2"),
        ("GET", "/frame?fov=400"),
        ("GET", "/frame?zoom=1e300"),
        ("GET", "/frame?eye=1e300,0,0"),
        ("GET", "/frame?size=100000x10"),
        ("GET", "/frame?spp=16"),
        ("GET", "/frame?output=x.png"),
        ("GET", "/frame?eye=1%2C2%2C3"),
        ("GET", long.as_str()),
        ("POST", "/frame"),
    ];
    for (method, target) in refused {
        let (status, body) = request(a, method, target);
        assert!((400..500).contains(&status), "{method} {}: {status} {}", &target[..target.len().min(40)], {
            String::from_utf8_lossy(&body)
        });
    }
    assert!(!d.join("x.png").exists(), "a request never writes a file");
    let (status, body) = get(a, "/frame?eye=2,2,2&target=0,0,0&size=32x32&spp=1");
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
    assert_eq!(&body[1..4], b"PNG");
}

/// Polls `/state` until its version passes `after`.
fn wait_for_version(address: &str, after: u64) -> serde_json::Value {
    let started = Instant::now();
    loop {
        let state: serde_json::Value = serde_json::from_slice(&get(address, "/state").1).unwrap();
        if state["version"].as_u64().unwrap() > after {
            return state;
        }
        assert!(started.elapsed() < Duration::from_secs(60), "no reload: {state}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn watch_reloads_and_keeps_the_last_good_picture_on_an_error() {
    let dir = Scratch::new();
    let d = dir.0.as_path();
    let scene = |radius: &str| {
        format!(
            "[image]\nsize = [64, 48]\nsamples = 1\n\n[camera]\neye = [3, -2, 1.5]\ntarget = [0, 0, 0]\n\n\
             [domain]\nmin = [-1, -1, -1]\nedge = 2\ndepth = 5\n\n\
             [[solid]]\nname = \"ball\"\nshape = {{ sphere = {{ center = [0, 0, 0], radius = {radius} }} }}\n"
        )
    };
    std::fs::write(d.join("s.toml"), scene("0.5")).unwrap();
    let viewer = view(d, &["s.toml", "--watch"]);
    let a = &viewer.address;
    let state = wait_for_version(a, 0);
    let (version, voxels) = (state["version"].as_u64().unwrap(), state["solids"][0]["voxels"].as_u64().unwrap());
    let small = get(a, "/frame?spp=1").1;
    // The file's time must move on for the watcher to see it.
    std::thread::sleep(Duration::from_millis(1100));
    std::fs::write(d.join("s.toml"), scene("0.9")).unwrap();
    let state = wait_for_version(a, version);
    assert!(state["error"].is_null(), "{state}");
    assert!(state["solids"][0]["voxels"].as_u64().unwrap() > voxels, "the bigger ball is shown: {state}");
    let large = get(a, "/frame?spp=1").1;
    assert!(large != small, "the frame follows the file");
    std::thread::sleep(Duration::from_millis(1100));
    let broken = scene("\"big\"");
    let line = 1 + broken.lines().position(|l| l.contains("big")).unwrap();
    std::fs::write(d.join("s.toml"), &broken).unwrap();
    let state = wait_for_version(a, state["version"].as_u64().unwrap());
    let error = state["error"].as_str().expect("the error is shown");
    assert!(error.contains(&format!("s.toml:{line}:")), "the error has its line and column: {error}");
    assert!(get(a, "/frame?spp=1").1 == large, "the last good picture stays");
}

/// Connects and sends `bytes` (a request, or the start of one).
fn send(address: &str, bytes: &[u8]) -> TcpStream {
    let mut stream = TcpStream::connect(address).unwrap();
    stream.write_all(bytes).unwrap();
    stream
}

/// The status of the answer on `stream` (waiting up to a minute), with its body.
fn answer(stream: &mut TcpStream) -> (u16, String) {
    stream.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    let mut response = Vec::new();
    // The server may close after answering with bytes of ours unread: a reset after
    // the answer is not a failure.
    let mut chunk = [0; 65536];
    loop {
        match stream.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => response.extend_from_slice(&chunk[..n]),
            Err(e) if e.kind() == std::io::ErrorKind::ConnectionReset && !response.is_empty() => break,
            Err(e) => panic!("no answer: {e} (after {} bytes)", response.len()),
        }
    }
    let text = String::from_utf8_lossy(&response).to_string();
    let status = text.split(' ').nth(1).and_then(|s| s.parse().ok()).unwrap_or_else(|| panic!("no status: {text:?}"));
    (status, text)
}

/// Asserts that an ordinary request is answered (within a generous minute) and that
/// the viewer is still running.
fn still_served(viewer: &mut Viewer, after: &str) {
    assert!(viewer.child.try_wait().unwrap().is_none(), "the viewer exited after {after}");
    let (status, body) = get(&viewer.address, "/state");
    assert_eq!(status, 200, "after {after}: {}", String::from_utf8_lossy(&body));
    let state: serde_json::Value = serde_json::from_slice(&body).unwrap();
    assert!(state["version"].as_u64().is_some(), "after {after}: {state}");
}

#[test]
fn hostile_clients_do_not_stop_the_server() {
    let dir = Scratch::new();
    let d = dir.0.as_path();
    octsolid(d, &["shape", "sphere", "--depth", "5", "-o", "ball.oct"]);
    let mut viewer = view(d, &["ball.oct"]);
    let a = viewer.address.clone();

    // A huge declared length: refused without reading (or allocating) it.
    let mut huge =
        send(&a, format!("GET /state HTTP/1.1\r\nHost: {a}\r\nContent-Length: 10000000000000\r\n\r\n").as_bytes());
    assert_eq!(answer(&mut huge).0, 413);
    still_served(&mut viewer, "a huge Content-Length");

    // A body declared and never sent, held open: the others are answered meanwhile, and
    // it gets its answer (the body is not read).
    let mut no_body = send(&a, format!("GET /state HTTP/1.1\r\nHost: {a}\r\nContent-Length: 100\r\n\r\n").as_bytes());
    still_served(&mut viewer, "a body declared and not sent");
    assert_eq!(answer(&mut no_body).0, 200);

    // Slow clients: heads that never end, held open.
    let slow: Vec<TcpStream> = (0..3).map(|_| send(&a, b"GET /state HTTP/1.1\r\nHost: 127")).collect();
    still_served(&mut viewer, "three slow heads");

    // A stalled reader: 1,000 pipelined requests for frames, never read.
    let frame = format!("GET /frame?size=1024x1024&spp=1 HTTP/1.1\r\nHost: {a}\r\n\r\n");
    let stalled = send(&a, frame.repeat(1000).as_bytes());
    still_served(&mut viewer, "1,000 pipelined requests never read");

    // An endless header line: refused at the head's limit, not read on for ever.
    let mut endless = send(&a, format!("GET /state HTTP/1.1\r\nHost: {a}\r\nX-Endless: ").as_bytes());
    endless.write_all(&vec![b'a'; 64 * 1024]).unwrap();
    assert_eq!(answer(&mut endless).0, 431);
    still_served(&mut viewer, "an endless header line");

    // A foreign Host (a page that rebound its name to this machine) is not answered;
    // this machine's names are.
    let port = a.rsplit(':').next().unwrap();
    for host in ["evil.example", &format!("evil.example:{port}"), &format!("127.0.0.1.evil.example:{port}")] {
        let mut foreign = send(&a, format!("GET /state HTTP/1.1\r\nHost: {host}\r\n\r\n").as_bytes());
        let (status, text) = answer(&mut foreign);
        assert_eq!(status, 421, "{host}: {text}");
        assert!(!text.contains("version"), "{host}: the state is not shown: {text}");
    }
    for host in ["localhost", &format!("localhost:{port}"), &format!("[::1]:{port}"), "127.0.0.1"] {
        let mut local = send(&a, format!("GET /state HTTP/1.1\r\nHost: {host}\r\n\r\n").as_bytes());
        let (status, text) = answer(&mut local);
        assert_eq!(status, 200, "{host}: {text}");
        assert!(text.contains("\"version\""), "{host}: {text}");
    }
    drop((slow, stalled));
    still_served(&mut viewer, "all of them");
}

#[test]
fn a_flood_of_connections_is_refused_beyond_the_queue_and_the_server_goes_on() {
    let dir = Scratch::new();
    let d = dir.0.as_path();
    octsolid(d, &["shape", "sphere", "--depth", "5", "-o", "ball.oct"]);
    let mut viewer = view(d, &["ball.oct"]);
    let a = viewer.address.clone();
    // 300 connections that send nothing: 8 workers wait for their heads and 56 wait in
    // the queue; every other one is told at once that the server is busy. The 64 are
    // told their heads came too late when the deadline (10 s from their acceptance)
    // passes.
    let mut flood: Vec<TcpStream> = (0..300).map(|_| TcpStream::connect(&a).unwrap()).collect();
    let statuses: Vec<u16> = flood.iter_mut().map(|s| answer(s).0).collect();
    let busy = statuses.iter().filter(|&&s| s == 503).count();
    assert!(statuses.iter().all(|s| [408, 503].contains(s)), "{statuses:?}");
    assert!((200..300).contains(&busy), "{busy} of 300 refused as busy: {statuses:?}");
    still_served(&mut viewer, "a flood of 300 connections");
}

#[test]
fn running_out_of_file_descriptors_does_not_stop_the_server() {
    let dir = Scratch::new();
    let d = dir.0.as_path();
    octsolid(d, &["shape", "sphere", "--depth", "5", "-o", "ball.oct"]);
    // The viewer with 32 descriptors: 40 idle connections leave it none to accept with.
    let mut command = Command::new("sh");
    command.args(["-c", "ulimit -n 32 && exec \"$0\" view ball.oct", env!("CARGO_BIN_EXE_octsolid")]);
    let mut viewer = start(d, command);
    let flood: Vec<TcpStream> = (0..40).map(|_| TcpStream::connect(&viewer.address).unwrap()).collect();
    // Long enough for the viewer to have met EMFILE many times over (it retries every
    // 100 ms); no timing is asserted.
    std::thread::sleep(Duration::from_secs(1));
    assert!(viewer.child.try_wait().unwrap().is_none(), "the viewer exited without descriptors");
    drop(flood);
    still_served(&mut viewer, "running out of file descriptors");
}

#[test]
fn frames_within_the_memory_budget_are_drawn_and_larger_ones_refused() {
    let dir = Scratch::new();
    let d = dir.0.as_path();
    octsolid(d, &["shape", "sphere", "--depth", "5", "-o", "ball.oct"]);
    let mut viewer = view(d, &["ball.oct", "--memory-budget", "4MiB"]);
    let (status, small) = get(&viewer.address, "/frame?size=64x48&spp=1");
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&small));
    assert_eq!(&small[1..4], b"PNG");
    // render's own estimate refuses the larger one under the same budget.
    let out = Command::new(env!("CARGO_BIN_EXE_octsolid"))
        .current_dir(d)
        .args(["render", "ball.oct", "--size", "1024x1024", "--spp", "2", "--memory-budget", "4MiB", "-o", "big.png"])
        .output()
        .unwrap();
    assert!(!out.status.success(), "render refuses it too");
    let (status, body) = get(&viewer.address, "/frame?size=1024x1024&spp=2");
    let message = String::from_utf8_lossy(&body);
    assert_eq!(status, 507, "{message}");
    assert!(message.contains("memory budget is 4.0 MiB"), "the refusal names the budget: {message}");
    still_served(&mut viewer, "a frame over the budget");
}
