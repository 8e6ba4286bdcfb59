//! Helpers shared by the integration tests.

mod review;
pub use review::reviewable;

/// Runs `work` on a pool of its own with one thread. The test harness already runs one test
/// per core; a test that also spread its particle loops over every core would leave each loop
/// waiting for a worker the other test's threads have preempted, at every step.
pub fn on_one_thread<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool of one thread")
        .install(work)
}

/// Renders `svg` with an independent renderer (resvg) and checks what a reader would see: it
/// parses, it draws something besides its white background at the size it declares, and every
/// text element, laid out with the machine's fonts, lies on the canvas. Where the machine has
/// no fonts, usvg cannot lay text out and the text part is skipped (`svg`'s own unit test
/// still checks every text anchor).
pub fn assert_renders(svg: &str, what: &str) {
    use resvg::{tiny_skia, usvg};
    let mut options = usvg::Options::default();
    let fonts = options.fontdb_mut();
    fonts.load_system_fonts();
    // the figures ask for the generic sans-serif: the first family the machine has stands in
    let families: Vec<String> = fonts
        .faces()
        .filter_map(|face| face.families.first().map(|(name, _)| name.clone()))
        .collect();
    let family = families
        .iter()
        .find(|name| name.contains("Sans") && !name.contains("Mono"))
        .or(families.first())
        .cloned();
    let have_fonts = family.is_some();
    if let Some(family) = family {
        fonts.set_sans_serif_family(family);
    }
    let tree = usvg::Tree::from_str(svg, &options)
        .unwrap_or_else(|e| panic!("{what}: the SVG does not parse: {e}"));
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .unwrap_or_else(|| panic!("{what}: empty canvas"));
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    assert!(
        pixmap
            .pixels()
            .iter()
            .any(|p| p.red() < 128 || p.blue() < 128),
        "{what}: nothing drawn"
    );
    if !have_fonts {
        return;
    }
    let (width, height) = (tree.size().width(), tree.size().height());
    let mut texts = Vec::new();
    collect_text_boxes(tree.root(), &mut texts);
    // text elements with something to show (an empty title lays out as nothing)
    let declared = svg
        .split("<text")
        .skip(1)
        .filter(|element| {
            let content = &element[element.find('>').map_or(0, |k| k + 1)..];
            !content.starts_with("</text>")
        })
        .count();
    assert_eq!(texts.len(), declared, "{what}: text elements laid out");
    for b in texts {
        // half a pixel of anti-aliasing either side
        assert!(
            b.left() >= -0.5
                && b.top() >= -0.5
                && b.right() <= width + 0.5
                && b.bottom() <= height + 0.5,
            "{what}: a text element runs off the {width} × {height} canvas: {b:?}"
        );
    }
}

fn collect_text_boxes(group: &resvg::usvg::Group, boxes: &mut Vec<resvg::usvg::Rect>) {
    for node in group.children() {
        match node {
            resvg::usvg::Node::Text(text) => boxes.push(text.abs_bounding_box()),
            resvg::usvg::Node::Group(inner) => collect_text_boxes(inner, boxes),
            _ => {}
        }
    }
}
