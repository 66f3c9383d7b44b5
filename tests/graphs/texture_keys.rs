//! Texture keys are unambiguous: an image path that would share its key with another
//! reference (a file `a.png|b.png` and the mip chain `["a.png", "b.png"]`; a file
//! `a.png#linear` and `a.png` read as linear; a mip level `scene:…` and the scene texture)
//! is refused at load, in either order, with an error naming the node and the path.

use matgraph::{Graph, Registry};
use std::process::Command;

/// A graph of two image nodes, `first` and `second`, with the given `"texture"` (and
/// optional `"color_space"`) JSON fragments.
fn two_images(first: &str, second: &str) -> String {
    format!(
        r#"{{ "version": 2, "name": "keys", "nodes": [
          {{ "id": "geo", "type": "geometry" }},
          {{ "id": "first", "type": "image_texture", {first}, "inputs": {{ "uv": {{ "link": "geo.uv" }} }} }},
          {{ "id": "second", "type": "image_texture", {second}, "inputs": {{ "uv": {{ "link": "geo.uv" }} }} }} ],
          "outputs": [
            {{ "name": "a", "from": "first.color" }},
            {{ "name": "b", "from": "second.color" }} ] }}"#
    )
}

/// The errors of loading `text`, as the user reads them.
fn errors(text: &str) -> Vec<String> {
    match Graph::from_json(text, Registry::builtin()) {
        Ok(_) => Vec::new(),
        Err(e) => e.iter().map(|e| e.to_string()).collect(),
    }
}

#[test]
fn a_pipe_in_a_file_name_is_refused_in_both_orders() {
    let file = r#""texture": "a.png|b.png""#;
    let chain = r#""texture": ["a.png", "b.png"]"#;
    let expected = "texture 'a.png|b.png': an image path may not contain '|', which joins the \
                    levels of a mip chain in texture keys (the file would share its key with \
                    the chain [\"a.png\", \"b.png\"]): rename the file";
    assert_eq!(
        errors(&two_images(file, chain)),
        [format!("node 'first': {expected}")]
    );
    assert_eq!(
        errors(&two_images(chain, file)),
        [format!("node 'second': {expected}")]
    );
    // A level of a chain with a '|' is the same ambiguity.
    let bad_level = r#""texture": ["a.png|b.png", "c.png"]"#;
    assert_eq!(
        errors(&two_images(bad_level, chain)),
        [format!("node 'first': {expected}")]
    );
    // The chain alone loads.
    assert_eq!(errors(&two_images(chain, r#""texture": "c.png""#)), [""; 0]);
}

#[test]
fn a_colour_space_suffix_in_a_file_name_is_refused_in_both_orders() {
    let file = r#""texture": "a.png#linear""#;
    let spaced = r#""texture": "a.png", "color_space": "linear""#;
    let expected = "texture 'a.png#linear': an image path may not end in '#linear', which marks \
                    the colour space in texture keys (the file would share its key with 'a.png' \
                    read with \"color_space\": \"linear\"): rename the file";
    assert_eq!(
        errors(&two_images(file, spaced)),
        [format!("node 'first': {expected}")]
    );
    assert_eq!(
        errors(&two_images(spaced, file)),
        [format!("node 'second': {expected}")]
    );
    for space in ["srgb", "data"] {
        let e = errors(&two_images(
            &format!(r#""texture": "x.exr#{space}""#),
            r#""texture": "c.png""#,
        ));
        assert_eq!(e.len(), 1, "{e:?}");
        assert!(
            e[0].contains(&format!("may not end in '#{space}'")),
            "{e:?}"
        );
    }
    // A '#' that names no colour space is part of the file name.
    assert_eq!(
        errors(&two_images(
            r#""texture": "odd#name.png""#,
            r#""texture": "a#b/c.png""#
        )),
        [""; 0]
    );
}

#[test]
fn a_scene_name_as_a_mip_level_is_refused() {
    let e = errors(&two_images(
        r#""texture": ["scene:refraction"]"#,
        r#""texture": "scene:refraction""#,
    ));
    assert_eq!(
        e,
        [
            "node 'first': texture level 'scene:refraction': a mip level may not start with \
          'scene:', which names the renderer's scene textures: rename the file"
        ]
    );
}

#[test]
fn check_names_the_file_the_node_and_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let graph = dir.path().join("g.json");
    std::fs::write(
        &graph,
        two_images(
            r#""texture": ["a.png", "b.png"]"#,
            r#""texture": "a.png|b.png""#,
        ),
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(["check", "g.json"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(String::from_utf8_lossy(&out.stdout), "g.json: 1 error\n");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.starts_with(
            "g.json: node 'second': texture 'a.png|b.png': an image path may not contain '|'"
        ),
        "{stderr}"
    );
}
