//! The real window under Xvfb, driven by synthetic keys (xdotool): the panel key shows the panel
//! and changes nothing else, a method key changes the shadows, and the screenshot key writes a
//! PNG of the window's size. Needs `Xvfb` and `xdotool` (CI installs them); without them the
//! test says so and checks nothing.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use umbra::render::Image;

fn installed(tool: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// A child process stopped when the test ends, passed or not: asked to end (so an X server
/// removes its lock), then killed if it is still there.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = Command::new("kill").arg(self.0.id().to_string()).status();
        for _ in 0..20 {
            if self.0.try_wait().is_ok_and(|s| s.is_some()) {
                return;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Starts Xvfb on a display it picks itself (free of every other server's), and names it. It
/// keeps running as it is when its last client leaves (`-noreset`): by default an X server resets
/// then, and a client connecting meanwhile (umbra, just after the readiness probe's xdotool
/// left) is refused.
fn start_xvfb() -> (Killed, String) {
    use std::io::BufRead;
    let mut xvfb = Command::new("Xvfb")
        .args(["-displayfd", "1", "-screen", "0", "1400x900x24", "-nolisten", "tcp", "-noreset"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    let out = xvfb.stdout.take().expect("piped");
    std::io::BufReader::new(out).read_line(&mut line).unwrap();
    let number: u32 = line.trim().parse().unwrap_or_else(|_| panic!("Xvfb named no display: {line:?}"));
    (Killed(xvfb), format!(":{number}"))
}

/// Waits up to `limit` for `ready` to give something.
fn wait_for<T>(what: &str, limit: Duration, mut ready: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(t) = ready() {
            return t;
        }
        assert!(start.elapsed() < limit, "gave up waiting for {what} after {limit:?}");
        std::thread::sleep(Duration::from_millis(200));
    }
}

fn xdotool(display: &str, args: &[&str]) -> String {
    let out = Command::new("xdotool").args(args).env("DISPLAY", display).output().unwrap();
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// Presses F12 and waits for screenshot `n` to be written.
fn screenshot(display: &str, dir: &Path, n: u32) -> Image {
    xdotool(display, &["key", "F12"]);
    let path: PathBuf = dir.join(format!("umbra-screenshot-{n}.png"));
    wait_for(&format!("{}", path.display()), Duration::from_secs(120), || common::read_png(&path))
}

/// Pixels where two pictures differ, as (x, y).
fn differing(a: &Image, b: &Image) -> Vec<(u32, u32)> {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let texels = a.pixels.chunks_exact(4).zip(b.pixels.chunks_exact(4));
    texels.enumerate().filter(|(_, (p, q))| p != q).map(|(i, _)| (i as u32 % a.width, i as u32 / a.width)).collect()
}

#[test]
fn keys_in_the_real_window_show_the_panel_change_the_method_and_save_screenshots() {
    if !installed("Xvfb") || !installed("xdotool") {
        eprintln!("SKIPPED: the window test needs Xvfb and xdotool (apt-get install xvfb xdotool)");
        return;
    }
    let dir = common::scratch("window");
    let (_xvfb, display) = start_xvfb();
    wait_for("Xvfb", Duration::from_secs(20), || {
        (!xdotool(&display, &["getdisplaygeometry"]).is_empty()).then_some(())
    });
    let runtime = common::scratch("window-runtime");
    let _umbra = Killed(
        Command::new(env!("CARGO_BIN_EXE_umbra"))
            // A held clock: nothing moves unless a key changes it.
            .args(["play", "--hold", "--time", "3"])
            .current_dir(&dir)
            .env("DISPLAY", &display)
            .env("XDG_RUNTIME_DIR", &runtime)
            .stdout(std::fs::File::create(dir.join("play.log")).unwrap())
            .spawn()
            .unwrap(),
    );
    let said = || std::fs::read_to_string(dir.join("play.log")).unwrap_or_default();
    let window = wait_for("the umbra window", Duration::from_secs(120), || {
        assert!(!said().contains("no display"), "umbra found no display at {display}: {}", said());
        let found = xdotool(&display, &["search", "--name", "^umbra"]);
        found.lines().next().map(str::to_string)
    });
    xdotool(&display, &["windowfocus", "--sync", &window]);

    let plain = screenshot(&display, &dir, 1);
    assert_eq!((plain.width, plain.height), (1280, 720), "the screenshot is the window's size");
    xdotool(&display, &["key", "Tab"]);
    let panel = screenshot(&display, &dir, 2);
    let changed = differing(&plain, &panel);
    let panel_width = changed.iter().map(|(x, _)| x + 1).max().unwrap_or(0);
    assert!(changed.len() > 20_000, "the panel shows: {} pixels changed", changed.len());
    assert!(
        (150..=500).contains(&panel_width),
        "pixels changed only in the panel on the left, up to x = {panel_width}"
    );
    xdotool(&display, &["key", "p"]);
    let method = screenshot(&display, &dir, 3);
    let scene: Vec<_> = differing(&panel, &method).into_iter().filter(|(x, _)| *x > panel_width + 4).collect();
    assert!(scene.len() > 200, "the next method (PCF 3x3) softens the shadows' edges: {} pixels", scene.len());
    xdotool(&display, &["key", "Escape"]);
}
