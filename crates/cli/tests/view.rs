//! `stride view` in a real browser: a short prediction writes `view.html` by default, and
//! the page opened from the file system in headless Chromium (software WebGL) renders a
//! frame without any error, with the model's pixels on screen. Skipped, with the reason
//! printed, where no Chromium is installed.

mod common;
use common::{rejects, stride};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A Chromium-family browser on the `PATH`, if any.
fn browser() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser", "google-chrome", "chrome"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |d| d.join(name)))
        .find(|p| p.is_file())
}

/// Runs the browser headless on `url` with `extra` arguments (a fresh profile, software
/// WebGL, no network, at most two minutes); returns stdout and stderr.
fn headless(browser: &Path, profile: &Path, url: &str, extra: &[&str]) -> (String, String) {
    let out = Command::new("timeout")
        .arg("120")
        .arg(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--host-resolver-rules=MAP * ~NOTFOUND",
            "--enable-logging=stderr",
            "--v=0",
            "--virtual-time-budget=4000",
            "--window-size=1200,800",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(url)
        .output()
        .expect("running the browser");
    assert!(out.status.success(), "browser failed: {out:?}");
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// RGB pixels of a PNG file.
fn pixels(path: &Path) -> (usize, usize, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::fs::File::open(path).expect("screenshot"));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let px = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    (info.width as usize, info.height as usize, px)
}

#[test]
fn predict_writes_a_page_that_renders_in_headless_chromium() {
    let root = std::env::temp_dir().join(format!("stride-view-cli-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let out = root.join("result");
    let run = stride(&[
        "predict",
        "--mesh",
        "10",
        "--presolve-mesh",
        "0",
        "--guess",
        "data-informed-walking",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{run:?}");
    let default_page = out.join("view.html");
    assert!(stdout.contains("viewer page"), "{stdout}");
    assert!(default_page.is_file(), "predict wrote no view.html");
    // `stride view` prints the page it wrote
    let page = root.join("page.html");
    let view = stride(&[
        "view",
        out.to_str().unwrap(),
        "--out",
        page.to_str().unwrap(),
    ]);
    assert!(view.status.success(), "{view:?}");
    assert_eq!(
        String::from_utf8_lossy(&view.stdout).trim(),
        page.display().to_string()
    );
    let Some(browser) = browser() else {
        eprintln!("skipping the browser check: no chromium on the PATH (apt-get install chromium)");
        let _ = std::fs::remove_dir_all(&root);
        return;
    };
    let url = format!("file://{}", page.display());
    // the page marks itself rendered after its first frame; errors would mark it `error`
    // and fill the (otherwise hidden) error box
    let (dom, log) = headless(
        &browser,
        &root.join("profile-dom"),
        &format!("{url}#play=0&t=0.3"),
        &["--dump-dom"],
    );
    assert!(
        dom.contains(r#"data-status="rendered""#),
        "page not rendered:\n{}",
        &dom[..dom.len().min(3000)]
    );
    assert!(
        dom.contains(r#"<pre id="errors" hidden=""></pre>"#),
        "errors shown: {dom:.3000}"
    );
    assert!(
        !log.contains("net::ERR"),
        "the page tried the network:\n{log}"
    );
    // a frame with the model and one without: not blank, and the model covers part of it
    let shot = |name: &str, hash: &str| {
        let png = root.join(name);
        headless(
            &browser,
            &root.join(format!("profile-{name}")),
            &format!("{url}#play=0&t=0.3&view=side{hash}"),
            &[&format!("--screenshot={}", png.display())],
        );
        pixels(&png)
    };
    let (w, h, with) = shot("model.png", "");
    let (_, _, without) = shot("empty.png", "&model=0");
    let distinct: std::collections::HashSet<[u8; 3]> = with.iter().copied().collect();
    assert!(
        distinct.len() > 100,
        "{} colours: a blank frame",
        distinct.len()
    );
    let differ = with
        .iter()
        .zip(&without)
        .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 24))
        .count();
    let share = differ as f64 / (w * h) as f64;
    assert!(
        share > 0.01,
        "the model covers {:.2} % of the frame",
        100.0 * share
    );
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn view_rejects_a_folder_without_results() {
    let dir = std::env::temp_dir().join(format!("stride-view-empty-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    rejects(
        &["view", dir.to_str().unwrap()],
        "not a result folder (no motion.mot)",
    );
    assert!(!dir.join("view.html").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
