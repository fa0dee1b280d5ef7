//! The loader against hostile and unusual files: what can hang or eat the machine is refused at
//! once, what glTF allows is accepted, what would draw a wrong picture is refused by name (or
//! mended with a warning), and textures are read, shared, or warned about.

mod common;

use common::gltf::*;
use common::scratch;
use glam::{Quat, Vec3};
use serde_json::json;
use std::path::Path;
use std::sync::mpsc;
use std::time::Duration;
use umbra::assets::{Filter, Model, Wrap, load_model, parse_model};

/// The model and its warnings for a changed copy of the test model, which must load.
fn accepted(change: impl FnOnce(&mut TestModel)) -> Model {
    let mut model = TestModel::new();
    change(&mut model);
    load(&model)
}

/// `load_model(path)` on a thread, failing the test if it takes more than 20 s (a hang).
fn load_in_time(path: &Path) -> Result<Model, String> {
    let (tx, rx) = mpsc::channel();
    let path = path.to_path_buf();
    std::thread::spawn(move || {
        let _ = tx.send(load_model(&path).map_err(|e| e.to_string()));
    });
    rx.recv_timeout(Duration::from_secs(20)).expect("loading hung")
}

#[cfg(unix)]
#[test]
fn pipes_devices_and_directories_are_refused_before_any_read() {
    let dir = scratch("special");
    let fifo = dir.join("model.glb");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs");
    assert!(made.success());
    let err = load_in_time(&fifo).unwrap_err();
    assert!(err.contains("model.glb: it is a named pipe (FIFO), not a file"), "{err}");
    for device in ["/dev/zero", "/dev/urandom"] {
        let err = load_in_time(Path::new(device)).unwrap_err();
        assert!(err.contains("it is a device"), "{device}: {err}");
    }
    let link = dir.join("zero.glb");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let err = load_in_time(&link).unwrap_err();
    assert!(err.contains("zero.glb: it is a device"), "{err}");
    let err = load_in_time(&dir).unwrap_err();
    assert!(err.contains("it is a directory"), "{err}");
    // A buffer beside the model that is a pipe is refused the same way.
    let (text, _) = TestModel::new().gltf_external("model.glb");
    std::fs::write(dir.join("column.gltf"), text).unwrap();
    let err = load_in_time(&dir.join("column.gltf")).unwrap_err();
    assert!(err.contains("buffer 0") && err.contains("named pipe"), "{err}");
}

#[test]
fn a_file_larger_than_the_limit_is_refused_by_its_size_unread() {
    // A sparse 3 GiB file whose .glb header claims 4 GiB: refused before a byte is read.
    let path = scratch("huge").join("huge.glb");
    let mut head = b"glTF".to_vec();
    head.extend(2u32.to_le_bytes());
    head.extend(u32::MAX.to_le_bytes());
    std::fs::write(&path, &head).unwrap();
    std::fs::OpenOptions::new().write(true).open(&path).unwrap().set_len(3 << 30).unwrap();
    let err = load_in_time(&path).unwrap_err();
    std::fs::remove_file(&path).unwrap();
    assert!(err.contains("huge.glb: it is 3 GiB, more than the 1 GiB umbra reads"), "{err}");
    // A header that claims more than the file holds is not trusted.
    let glb = TestModel::new().glb();
    let mut lying = glb.clone();
    lying[8..12].copy_from_slice(&(glb.len() as u32 * 4).to_le_bytes());
    let err = parse_model(&lying, None, "lying.glb").unwrap_err().to_string();
    assert!(err.contains("header says") && err.contains(&format!("the file has {}", glb.len())), "{err}");
}

#[test]
fn valid_files_are_accepted() {
    // extras may be any JSON value.
    let model = accepted(|m| {
        m.json["extras"] = json!(1);
        m.json["nodes"][0]["extras"] = json!("a string");
        m.json["meshes"][0]["extras"] = json!([1, 2]);
        m.json["asset"]["extras"] = json!(null);
    });
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    // A channel without a target node is ignored with a warning, the others still play.
    let model = accepted(|m| {
        let channels = m.json["animations"][0]["channels"].as_array_mut().unwrap();
        channels.push(json!({ "sampler": 0, "target": { "path": "rotation" } }));
    });
    assert!(model.warnings.iter().any(|w| w.contains("animation 0 channel 3 targets no node")), "{:?}", model.warnings);
    assert_eq!(model.clips[0].channels.len(), 3);
    // Minor versions above 2.0 are glTF 2.
    accepted(|m| m.json["asset"] = json!({ "version": "2.1", "minVersion": "2.0" }));
}

#[test]
fn unsupported_versions_are_refused() {
    for (asset, says) in [
        (json!({ "version": "1.0" }), "asset.version is \"1.0\"; umbra reads glTF 2.0"),
        (json!({ "version": "3.0" }), "asset.version is \"3.0\""),
        (json!({ "version": "2.0", "minVersion": "2.1" }), "asset.minVersion is \"2.1\""),
    ] {
        let err = refused(|m| m.json["asset"] = asset.clone());
        assert!(err.contains(says), "{err}");
    }
}

#[test]
fn errors_name_the_rule_once() {
    let err = refused(|m| m.json["accessors"][0]["bufferView"] = json!(77));
    assert!(err.contains("accessors[0].bufferView names an object that does not exist"), "{err}");
    assert_eq!(err.matches("glTF").count(), 1, "no doubled prefix: {err}");
    let glb = TestModel::new().glb();
    let mut empty = glb.clone();
    empty[12..16].copy_from_slice(&0u32.to_le_bytes());
    let err = parse_model(&empty, None, "empty.glb").unwrap_err().to_string();
    assert_eq!(err, "empty.glb: the .glb's JSON chunk is empty");
}

#[test]
fn animation_keys_are_checked_by_name() {
    let nan_key = |m: &mut TestModel| {
        let keys = m.add_floats(&[0.0, 0.0, 0.0, 1.0, 0.0, f32::NAN, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0], "VEC4");
        m.json["animations"][0]["samplers"][0]["output"] = json!(keys);
    };
    let err = refused(nan_key);
    assert!(err.contains("animation 0 channel 0: rotation key 1 is NaN"), "{err}");
    let err = refused(|m| {
        let times = m.add_floats(&[0.0, 1.0, 0.5], "SCALAR");
        m.json["animations"][0]["samplers"][0]["input"] = json!(times);
    });
    assert!(err.contains("animation 0 channel 0: key time 2 (0.5 s) comes before key time 1 (1 s)"), "{err}");
    let err = refused(|m| {
        let keys = m.add_floats(&[0.0; 12], "VEC4");
        m.json["animations"][0]["samplers"][0]["output"] = json!(keys);
    });
    assert!(err.contains("rotation key 0 has length 0"), "{err}");
    let err = refused(|m| m.json["accessors"][6]["count"] = json!(0));
    assert!(err.contains("animation 0 sampler 0 has no keys"), "{err}");
    // Equal key times are a step; all-zero times hold one pose: both load, with a warning.
    let model = accepted(|m| {
        let times = m.add_floats(&[0.0, 1.0, 1.0], "SCALAR");
        m.json["animations"][0]["samplers"][0]["input"] = json!(times);
    });
    assert!(model.warnings.iter().any(|w| w.contains("key times 1 and 2 are both 1 s")), "{:?}", model.warnings);
    let rotation = |t: f32| {
        let mut locals = model.rest_locals();
        model.clips[0].apply(t, &mut locals);
        locals[1].rotation
    };
    assert!(rotation(0.999).angle_between(Quat::from_rotation_z(TIP_ANGLES[1])) < 0.01);
    assert!(rotation(1.0).abs_diff_eq(Quat::from_rotation_z(TIP_ANGLES[2]), 1e-6), "the step lands on the later key");
    let model = accepted(|m| {
        let times = m.add_floats(&[0.0, 0.0, 0.0], "SCALAR");
        m.json["animations"][0]["samplers"][0]["input"] = json!(times);
    });
    assert!(model.warnings.iter().any(|w| w.contains("every one of its 3 key times is 0 s")), "{:?}", model.warnings);
}

#[test]
fn rotation_keys_of_any_length_are_made_unit() {
    // The same keys scaled by 1e30: finite, but their squares overflow a float.
    let scaled: Vec<f32> =
        TIP_ANGLES.iter().flat_map(|a| [0.0, 0.0, (a / 2.0).sin(), (a / 2.0).cos()].map(|c| c * 1e30)).collect();
    let model = accepted(|m| {
        let keys = m.add_floats(&scaled, "VEC4");
        m.json["animations"][0]["samplers"][0]["output"] = json!(keys);
    });
    let plain = load(&TestModel::new());
    for t in [0.0, 0.5, 1.0, 1.5] {
        let (a, b) = (model.pose(Some(0), t), plain.pose(Some(0), t));
        assert!(a.iter().zip(&b).all(|(x, y)| x.abs_diff_eq(*y, 1e-5)), "at {t}: {a:?}");
    }
}

#[test]
fn layouts_that_break_the_rules_are_refused_by_the_rule() {
    let err = refused(|m| m.json["accessors"][4]["count"] = json!(0));
    assert!(err.contains("accessor 4 has no elements (count 0)"), "{err}");
    let err = refused(|m| m.json["bufferViews"][0]["byteStride"] = json!(6));
    assert!(err.contains("buffer view 0: its byteStride of 6 bytes is not a multiple of 4"), "{err}");
    let err = refused(|m| {
        m.json["accessors"][1]["byteOffset"] = json!(2);
        m.json["accessors"][1]["count"] = json!(11);
    });
    assert!(
        err.contains("accessor 1 starts at byte") && err.contains("not on a multiple of its 4-byte components"),
        "{err}"
    );
    let err = refused(|m| m.json["buffers"][0]["byteLength"] = json!(100));
    assert!(err.contains("past the 100 bytes that buffer 0 declares"), "{err}");
    // Positions stored as bytes need KHR_mesh_quantization.
    let bytes: Vec<u8> = (0..12).flat_map(|i| [(i % 2) as u8, (i / 4) as u8, (i % 3) as u8, 0]).collect();
    let as_bytes = |m: &mut TestModel| {
        let at = m.bin.len();
        m.bin.extend(&bytes);
        m.json["buffers"][0]["byteLength"] = json!(m.bin.len());
        let views = m.json["bufferViews"].as_array_mut().unwrap();
        views.push(json!({ "buffer": 0, "byteOffset": at, "byteLength": 48, "byteStride": 4 }));
        let view = views.len() - 1;
        m.json["accessors"][0] = json!({ "bufferView": view, "componentType": 5121, "count": 12, "type": "VEC3",
            "min": [0, 0, 0], "max": [1, 2, 2] });
    };
    let err = refused(as_bytes);
    assert!(
        err.contains("POSITION (accessor 0) holds unsigned bytes, but glTF allows only floats there")
            && err.contains("KHR_mesh_quantization"),
        "{err}"
    );
    let model = accepted(|m| {
        as_bytes(m);
        m.json["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
    });
    assert_eq!(model.parts[0].mesh.vertices[5].position, [1.0, 1.0, 2.0]);
    // ... and their elements must start on 4-byte boundaries even then.
    let err = refused(|m| {
        as_bytes(m);
        m.json["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
        let last = m.json["bufferViews"].as_array().unwrap().len() - 1;
        m.json["bufferViews"][last].as_object_mut().unwrap().remove("byteStride");
    });
    assert!(err.contains("must start on a 4-byte boundary, but its elements are 3 bytes apart"), "{err}");
}

#[test]
fn a_model_with_no_size_is_placed_unscaled_and_one_not_finite_is_refused() {
    let model = accepted(|m| {
        let same = m.add_floats(&[0.5; 36], "VEC3");
        m.json["accessors"][same]["min"] = json!([0.5, 0.5, 0.5]);
        m.json["accessors"][same]["max"] = json!([0.5, 0.5, 0.5]);
        m.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(same);
    });
    assert!(
        model.warnings.iter().any(|w| w.contains("0 m across") && w.contains("placed unscaled")),
        "{:?}",
        model.warnings
    );
    let placed = umbra::scene::stand_at(&model, Vec3::ZERO);
    assert_eq!(placed.scale, Vec3::ONE, "not blown up by millions");
    let err = refused(|m| {
        m.json["nodes"][0]["scale"] = json!([3e38, 3e38, 3e38]);
        m.json["nodes"][1]["scale"] = json!([3e38, 3e38, 3e38]);
    });
    assert!(err.contains("rest pose is not finite"), "{err}");
}

#[test]
fn instanced_meshes_are_built_once_and_shared() {
    let model = accepted(|m| {
        m.json["nodes"][2].as_object_mut().unwrap().remove("skin");
        let nodes = m.json["nodes"].as_array_mut().unwrap();
        for i in 0..10 {
            nodes.push(json!({ "mesh": 0, "translation": [i as f32, 0.0, 0.0] }));
        }
        m.json["scenes"][0]["nodes"] = json!((0..13).filter(|&n| n != 1).collect::<Vec<_>>());
    });
    assert_eq!(model.parts.len(), 11);
    assert!(model.parts.iter().all(|p| std::sync::Arc::ptr_eq(&p.mesh, &model.parts[0].mesh)));
    let err = refused(|m| {
        let primitive = m.json["meshes"][0]["primitives"][0].clone();
        m.json["meshes"][0]["primitives"] = json!(vec![primitive; 2000]);
        let nodes = m.json["nodes"].as_array_mut().unwrap();
        nodes.extend((0..100).map(|_| json!({ "mesh": 0 })));
        m.json["scenes"][0]["nodes"] = json!((0..103).filter(|&n| n != 1).collect::<Vec<_>>());
    });
    assert!(err.contains("its scene draws 202000 mesh parts") && err.contains("at most 131072"), "{err}");
}

#[test]
fn a_required_texture_transform_moves_the_texture_coordinates_it_names() {
    let png = png_rgba(4, 4, &checker(4, [255, 0, 0, 255], [0, 0, 255, 0]));
    let transformed = |transform: serde_json::Value| {
        let mut m = TestModel::new().with_texture(&png, None);
        m.json["extensionsUsed"] = json!(["KHR_texture_transform"]);
        m.json["extensionsRequired"] = json!(["KHR_texture_transform"]);
        m.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
            json!({ "KHR_texture_transform": transform });
        load(&m)
    };
    // Vertex 5 reads (0.25, 0.5): scaled (0.5, 1), turned a quarter (u to v) to (-1, 0.5), offset.
    let model =
        transformed(json!({ "offset": [0.5, 0.0], "rotation": std::f32::consts::FRAC_PI_2, "scale": [2.0, 2.0] }));
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    let uv = model.parts[0].mesh.vertices[5].uv;
    assert!((uv[0] + 0.5).abs() < 1e-6 && (uv[1] - 0.5).abs() < 1e-6, "{uv:?}");
    assert!(model.parts[0].texture.is_some());
    // Its own texCoord overrides the texture's: TEXCOORD_1, which the column lacks.
    let model = transformed(json!({ "texCoord": 1 }));
    assert!(model.parts[0].texture.is_none());
    assert!(model.warnings.iter().any(|w| w.contains("TEXCOORD_1")), "{:?}", model.warnings);
    // A scale past f32's range is not finite: refused, naming the texture and the rule.
    let mut m = TestModel::new().with_texture(&png, None);
    m.json["extensionsUsed"] = json!(["KHR_texture_transform"]);
    m.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
        json!({ "KHR_texture_transform": { "scale": [1e39, 1.0] } });
    let err = match umbra::assets::parse_model(&m.glb(), None, "far.glb") {
        Ok(_) => panic!("a transform that is not finite loaded"),
        Err(e) => e.to_string(),
    };
    assert!(err.contains("far.glb") && err.contains("texture") && err.contains("not finite"), "{err}");
}

#[test]
fn a_texture_coordinate_accessor_of_the_wrong_type_is_refused_where_read_and_warned_of_elsewhere() {
    let png = png_rgba(4, 4, &checker(4, [255, 0, 0, 255], [0, 0, 255, 0]));
    let retyped = |set: &str, kind: &str, component: u32| {
        let mut m = TestModel::new().with_texture(&png, None);
        let values = m.add_floats(&[0.5; 36], "VEC3");
        m.json["accessors"][values]["type"] = json!(kind);
        m.json["accessors"][values]["componentType"] = json!(component);
        m.json["meshes"][0]["primitives"][0]["attributes"][set] = json!(values);
        m
    };
    let refusal = |m: &TestModel| match umbra::assets::parse_model(&m.glb(), None, "uv.glb") {
        Ok(_) => panic!("a texture read through a broken accessor loaded"),
        Err(e) => e.to_string(),
    };
    // The set the texture reads: three floats per element, or 32-bit integers, are refused.
    let err = refusal(&retyped("TEXCOORD_0", "VEC3", 5126));
    assert!(
        err.contains("mesh 0 primitive 0") && err.contains("TEXCOORD_0 has 3 components per element, not 2"),
        "{err}"
    );
    let err = refusal(&retyped("TEXCOORD_0", "VEC2", 5125));
    assert!(err.contains("TEXCOORD_0") && err.contains("uv.glb"), "{err}");
    // A set nothing reads is warned of by name and left out.
    let model = load(&retyped("TEXCOORD_1", "VEC3", 5126));
    assert!(model.parts[0].texture.is_some());
    let warned =
        model.warnings.iter().find(|w| w.contains("TEXCOORD_1")).unwrap_or_else(|| panic!("{:?}", model.warnings));
    assert!(
        warned.contains("primitive 0: TEXCOORD_1 has 3 components per element, not 2") && warned.contains("ignored"),
        "{warned}"
    );
    assert_eq!(model.warnings.len(), 1, "{:?}", model.warnings);
}

#[test]
fn textures_are_read_with_their_sampler_and_shared() {
    let red_blue = checker(4, [255, 0, 0, 255], [0, 0, 255, 0]);
    let sampler = json!({ "magFilter": 9728, "minFilter": 9984, "wrapS": 33071, "wrapT": 33648 });
    let model = load(&TestModel::new().with_texture(&png_rgba(4, 4, &red_blue), Some(sampler)));
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    let texture = model.parts[0].texture.as_ref().expect("a texture");
    assert_eq!((texture.image.width, texture.image.height, texture.image.levels.len()), (4, 4, 3));
    assert_eq!(texture.image.levels[0], red_blue);
    assert_eq!(
        (texture.sampling.mag, texture.sampling.min, texture.sampling.mipmap),
        (Filter::Nearest, Filter::Nearest, Some(Filter::Nearest))
    );
    assert_eq!(texture.sampling.wrap, [Wrap::ClampToEdge, Wrap::MirroredRepeat]);
    let uv: Vec<[f32; 2]> = model.parts[0].mesh.vertices.iter().map(|v| v.uv).collect();
    assert_eq!((uv[5], uv[11]), ([0.25, 0.5], [0.75, 1.0]));
    // The same image in a data URI.
    let mut inline = TestModel::new().with_texture(&png_rgba(4, 4, &red_blue), None);
    let data = base64::Engine::encode(&base64::engine::general_purpose::STANDARD, png_rgba(4, 4, &red_blue));
    inline.json["images"] = json!([{ "uri": format!("data:image/png;base64,{data}") }]);
    assert_eq!(load(&inline).parts[0].texture.as_ref().unwrap().image.levels[0], red_blue);
    // Two primitives with the material share one texture.
    let mut twice = TestModel::new().with_texture(&png_rgba(4, 4, &red_blue), None);
    let primitive = twice.json["meshes"][0]["primitives"][0].clone();
    twice.json["meshes"][0]["primitives"] = json!([primitive.clone(), primitive]);
    let model = load(&twice);
    let (a, b) = (model.parts[0].texture.as_ref().unwrap(), model.parts[1].texture.as_ref().unwrap());
    assert!(std::sync::Arc::ptr_eq(a, b));
}

#[test]
fn a_missing_or_broken_image_is_a_warning_and_the_factor_alone_is_used() {
    let mut missing = TestModel::new().with_texture(&png_rgba(1, 1, &[9; 4]), None);
    missing.json["images"] = json!([{ "uri": "gone.png" }]);
    let dir = scratch("missing-image");
    std::fs::write(dir.join("model.glb"), missing.glb()).unwrap();
    let model = load_model(&dir.join("model.glb")).unwrap();
    assert!(model.parts[0].texture.is_none());
    assert_eq!(model.parts[0].material.base_color, Vec3::new(0.2, 0.4, 0.6));
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.contains("image 0 (gone.png) cannot be read") && w.contains("base colour alone")),
        "{:?}",
        model.warnings
    );
    let png = png_rgba(4, 4, &[9; 64]);
    let broken = TestModel::new().with_texture(&png[..png.len() - 20], None);
    let model = load(&broken);
    assert!(model.parts[0].texture.is_none());
    assert!(model.warnings.iter().any(|w| w.contains("image 0 (checker) cannot be read")), "{:?}", model.warnings);
    // An image wider than umbra keeps: drawn from its first mipmap that fits, and said so.
    let wide = umbra::assets::MAX_KEPT_SIZE * 2;
    let model = load(&TestModel::new().with_texture(&png_rgba(wide, 2, &vec![9; wide as usize * 8]), None));
    let image = &model.parts[0].texture.as_ref().unwrap().image;
    assert_eq!((image.width, image.height), (wide / 2, 1));
    let said = |w: &String| w.contains(&format!("image 0 (checker) is {wide}x2; it is drawn at {}x1", wide / 2));
    assert!(model.warnings.iter().any(said), "{:?}", model.warnings);
    // A JPEG cut short: refused by name and why, not drawn grey past the cut.
    let jpeg = include_bytes!("../src/assets/test_images/gradient.jpg");
    let model = load(&TestModel::new().with_texture(&jpeg[..jpeg.len() * 2 / 3], None));
    assert!(model.parts[0].texture.is_none());
    let said = |w: &String| w.contains("image 0 (checker) cannot be read (a broken JPEG, cut short");
    assert!(model.warnings.iter().any(said), "{:?}", model.warnings);
    let mut no_uv = TestModel::new().with_texture(&png, None);
    no_uv.json["meshes"][0]["primitives"][0]["attributes"].as_object_mut().unwrap().remove("TEXCOORD_0");
    let model = load(&no_uv);
    assert!(model.parts[0].texture.is_none());
    assert!(model.warnings.iter().any(|w| w.contains("TEXCOORD_0, which it lacks")), "{:?}", model.warnings);
}

#[test]
fn materials_carry_alpha_mode_sides_and_vertex_colours() {
    use umbra::components::AlphaMode;
    let model = accepted(|m| {
        m.json["materials"][0]["alphaMode"] = json!("MASK");
        m.json["materials"][0]["alphaCutoff"] = json!(0.3);
        m.json["materials"][0]["doubleSided"] = json!(true);
        m.json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = json!([1.0, 1.0, 1.0, 0.5]);
        let colors = m.add_floats(&[0.25; 48], "VEC4");
        m.json["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = json!(colors);
    });
    let part = &model.parts[0];
    assert_eq!(part.material.alpha_mode, AlphaMode::Mask { cutoff: 0.3 });
    assert!(part.material.double_sided);
    assert_eq!(part.material.opacity, 0.5);
    assert_eq!(part.mesh.vertices[0].color, [0.25; 4]);
    let blend = accepted(|m| m.json["materials"][0]["alphaMode"] = json!("BLEND"));
    assert_eq!(blend.parts[0].material.alpha_mode, AlphaMode::Blend);
    assert_eq!(blend.parts[0].material.alpha_mode.cutoff(), Some(0.5), "a blended caster casts as masked at 0.5");
    let plain = load(&TestModel::new());
    assert_eq!(plain.parts[0].material.alpha_mode, AlphaMode::Opaque);
    assert_eq!(plain.parts[0].mesh.vertices[0].color, [1.0; 4]);
}

/// JSON pointers to every value inside `v`.
fn pointers(v: &serde_json::Value, at: String, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Object(m) => m.iter().for_each(|(k, x)| pointers(x, format!("{at}/{k}"), out)),
        serde_json::Value::Array(a) => a.iter().enumerate().for_each(|(i, x)| pointers(x, format!("{at}/{i}"), out)),
        _ => {}
    }
    out.push(at);
}

/// The .glb of `json` with `bin`.
fn glb_of(json: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    TestModel { json: json.clone(), bin: bin.to_vec() }.glb()
}

#[test]
fn structured_corruptions_never_panic() {
    // Every value of the JSON of a textured model and of the character, in turn, replaced by
    // values meant to break a loader: negative, zero, huge, the wrong type, empty. Each gives
    // a model or an error; whatever loads must pose.
    let textured = TestModel::new().with_texture(&png_rgba(4, 4, &checker(4, [255; 4], [0; 4])), None);
    let glb = umbra::scene::CHARACTER_GLB;
    let json_len = u32::from_le_bytes([glb[12], glb[13], glb[14], glb[15]]) as usize;
    let character = TestModel {
        json: serde_json::from_slice(&glb[20..20 + json_len]).unwrap(),
        bin: glb[28 + json_len..].to_vec(),
    };
    let hostile = [
        json!(-1),
        json!(0),
        json!(3),
        json!(65535),
        json!(4294967296u64),
        json!(1e30),
        json!("x"),
        json!(null),
        json!([]),
        json!({}),
    ];
    let mut outcomes = (0, 0);
    for (model, every) in [(&textured, 1), (&character, 7)] {
        let mut all = Vec::new();
        pointers(&model.json, String::new(), &mut all);
        for (k, at) in all.iter().enumerate().filter(|(k, at)| k % every == 0 && !at.is_empty()) {
            for value in &hostile {
                let mut json = model.json.clone();
                *json.pointer_mut(at).unwrap() = value.clone();
                match parse_model(&glb_of(&json, &model.bin), None, "corrupt.glb") {
                    Ok(m) => {
                        outcomes.0 += 1;
                        let globals = m.pose(m.clips.first().map(|_| 0), 0.4 + k as f32 * 1e-3);
                        for part in &m.parts {
                            let _ = m.part_bounds(part, &globals, &glam::Mat4::IDENTITY);
                        }
                    }
                    Err(e) => {
                        outcomes.1 += 1;
                        assert!(e.to_string().starts_with("corrupt.glb: "), "{e}");
                    }
                }
            }
        }
    }
    // And the texture's bytes flipped one at a time: a warning at worst.
    let view = textured.json["images"][0]["bufferView"].as_u64().unwrap() as usize;
    let start = textured.json["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
    let len = textured.json["bufferViews"][view]["byteLength"].as_u64().unwrap() as usize;
    for i in 0..len {
        let mut bin = textured.bin.clone();
        bin[start + i] ^= 0x5a;
        let m = parse_model(&glb_of(&textured.json, &bin), None, "flipped.glb").expect("a broken image only warns");
        assert!(m.parts[0].texture.is_some() || m.warnings.iter().any(|w| w.contains("image 0")), "{i}");
    }
    eprintln!("{} corrupted files loaded, {} refused", outcomes.0, outcomes.1);
    assert!(outcomes.0 > 100 && outcomes.1 > 1000, "{outcomes:?}");
}
