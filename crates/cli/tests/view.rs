//! `stride view` in a real browser: a short prediction writes `view.html` by default, and
//! the page opened from the file system in headless Chromium (software WebGL) renders a
//! frame without any error, with the model's pixels on screen; likewise the page of a tiny
//! real study (two speeds), with both cases selectable and the study's figures. The
//! browser checks are skipped, with the reason printed, where no Chromium is installed.

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

/// The DOM of the page at `url` after its first frame, checked: the page marks itself
/// rendered (errors would mark it `error` and fill the otherwise hidden error box) and
/// tried no network address.
fn rendered_dom(browser: &Path, root: &Path, url: &str) -> String {
    let (dom, log) = headless(browser, &root.join("profile-dom"), url, &["--dump-dom"]);
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
    dom
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
    assert_eq!(
        String::from_utf8_lossy(&run.stderr),
        "",
        "--quiet printed on stderr"
    );
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
    rendered_dom(&browser, &root, &format!("{url}#play=0&t=0.3"));
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

/// A study of two converged cases (1.2 and 1.4 m/s, 10 intervals, one guess).
const TINY_STUDY: &str = "[study]\nname = \"tiny\"\noutput = \"unused\"\njobs = 2\n\
guesses = [\"data-informed-walking\"]\n[study.solver]\npresolve_mesh = 0\n\
[base]\nmesh_intervals = 10\n[grid]\nspeed = [1.2, 1.4]\n";

#[test]
fn a_real_study_writes_a_page_with_every_case_that_renders_in_headless_chromium() {
    let root = std::env::temp_dir().join(format!("stride-view-study-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let file = root.join("tiny.toml");
    std::fs::write(&file, TINY_STUDY).unwrap();
    let out = root.join("study");
    let run = stride(&[
        "study",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(run.status.success(), "{run:?}");
    let page = out.join("view.html");
    assert!(page.is_file(), "study wrote no view.html");
    let html = std::fs::read_to_string(&page).unwrap();
    let cases = ["speed_1.2__diw", "speed_1.4__diw"];
    for c in cases {
        assert!(html.contains(c), "the page lacks case {c}");
    }
    assert!(
        html.contains("figure_speed_series_0"),
        "the page lacks the speed figure"
    );
    let Some(browser) = browser() else {
        eprintln!("skipping the browser check: no chromium on the PATH (apt-get install chromium)");
        let _ = std::fs::remove_dir_all(&root);
        return;
    };
    let url = format!("file://{}", page.display());
    let dom = rendered_dom(&browser, &root, &format!("{url}#play=0&t=0.3&case=1"));
    // both cases in the selector, the second one shown, the figures listed
    for (i, c) in cases.iter().enumerate() {
        assert!(
            dom.contains(&format!(r#"<option value="{i}">{c}</option>"#)),
            "no option for {c}"
        );
    }
    assert!(
        dom.contains(&format!(r#"id="case-title">{}</"#, cases[1])),
        "case 1 not shown"
    );
    assert!(dom.contains("figure-list") && dom.contains("<figure"));
    let png = root.join("study.png");
    headless(
        &browser,
        &root.join("profile-shot"),
        &format!("{url}#play=0&t=0.3&view=side&case=1"),
        &[&format!("--screenshot={}", png.display())],
    );
    let (_, _, px) = pixels(&png);
    let distinct: std::collections::HashSet<[u8; 3]> = px.iter().copied().collect();
    assert!(
        distinct.len() > 100,
        "{} colours: a blank frame",
        distinct.len()
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
