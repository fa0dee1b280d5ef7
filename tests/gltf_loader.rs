//! The glTF loader: a skinned model loads the same from .glb, embedded and external .gltf; its
//! rest pose is its bind pose; its clip samples as the keys say; and each way a file can be
//! broken gives an error naming the file and the problem, or a warning and a sane result.

mod common;

use common::gltf::*;
use common::scratch;
use glam::{Mat4, Quat, Vec3};
use serde_json::json;
use std::path::Path;
use umbra::assets::skin::skin_vertices;
use umbra::assets::{Model, load_model, parse_model};

#[test]
fn glb_embedded_and_external_gltf_load_the_same_model() {
    let model = TestModel::new();
    let from_glb = load(&model);
    let from_text = parse_model(&model.gltf_embedded(), None, "test.gltf").unwrap();
    let dir = scratch("external");
    let (text, bin) = model.gltf_external("column data.bin");
    std::fs::write(dir.join("column.gltf"), text).unwrap();
    std::fs::write(dir.join("column data.bin"), bin).unwrap();
    let from_files = load_model(&dir.join("column.gltf")).unwrap();
    for other in [&from_text, &from_files] {
        assert_eq!(other.parts, from_glb.parts);
        assert_eq!(other.skins, from_glb.skins);
        assert_eq!(other.clips, from_glb.clips);
    }
    assert_eq!(from_glb.parts.len(), 1);
    assert_eq!(from_glb.parts[0].mesh.vertices.len(), 12);
    assert_eq!(from_glb.parts[0].mesh.triangle_count(), 16);
    assert_eq!(from_glb.parts[0].material.base_color, Vec3::new(0.2, 0.4, 0.6));
    assert!(from_glb.warnings.is_empty(), "{:?}", from_glb.warnings);
}

#[test]
fn the_rest_pose_reproduces_the_bind_pose() {
    for (name, model) in [("test", load(&TestModel::new())), ("character", character())] {
        let globals = model.pose(None, 0.0);
        for part in &model.parts {
            let joints = model.joint_matrices(part.skin.unwrap(), &globals);
            for (posed, bind) in skin_vertices(&part.mesh, &joints).iter().zip(&part.mesh.vertices) {
                assert!(Vec3::from(posed.position).abs_diff_eq(Vec3::from(bind.position), 1e-5), "{name}");
                assert!(Vec3::from(posed.normal).abs_diff_eq(Vec3::from(bind.normal), 1e-5), "{name}");
            }
        }
    }
}

fn character() -> Model {
    parse_model(umbra::scene::CHARACTER_GLB, None, "character.glb").unwrap()
}

#[test]
fn joint_matrices_compose_parent_times_local() {
    let model = load(&TestModel::new());
    let globals = model.pose(Some(0), 0.5);
    let (root, tip) = (0, 1);
    let mut locals = model.rest_locals();
    model.clips[0].apply(0.5, &mut locals);
    assert!(globals[tip].abs_diff_eq(locals[root].matrix() * locals[tip].matrix(), 1e-6));
    // The middle ring is half root, half tip: it moves half as far as the tip's rotation would.
    let joints = model.joint_matrices(0, &globals);
    let posed = skin_vertices(&model.parts[0].mesh, &joints);
    let mid = Vec3::from(model.parts[0].mesh.vertices[4].position);
    let want = (joints[0].transform_point3(mid) + joints[1].transform_point3(mid)) * 0.5;
    assert!(Vec3::from(posed[4].position).abs_diff_eq(want, 1e-6));
}

#[test]
fn clips_sample_keys_exactly_interpolate_between_and_loop() {
    let model = load(&TestModel::new());
    let clip = &model.clips[0];
    assert_eq!((clip.name.as_str(), clip.duration), ("bend", 2.0));
    let pose = |t: f32| {
        let mut locals = model.rest_locals();
        clip.apply(t, &mut locals);
        locals
    };
    // A key time gives the key: LINEAR rotation, STEP translation, CUBICSPLINE scale.
    let at_key = pose(1.0);
    assert!(at_key[1].rotation.abs_diff_eq(Quat::from_rotation_z(TIP_ANGLES[1]), 1e-6));
    assert_eq!(at_key[0].translation.x, ROOT_X[1]);
    assert_eq!(at_key[1].scale, Vec3::splat(TIP_SCALE[1]));
    // Between keys: LINEAR slerps, STEP holds, CUBICSPLINE follows its out-tangent.
    let between = pose(0.5);
    assert!(between[1].rotation.abs_diff_eq(Quat::from_rotation_z(TIP_ANGLES[1] / 2.0), 1e-5));
    assert_eq!(between[0].translation.x, ROOT_X[0]);
    // Hermite from 1 (out-tangent 1.5, dt 1) to 2 (in-tangent 0) at s = 0.5:
    // 1·0.5 + 1.5·0.125 + 2·0.5 + 0 = 1.6875.
    assert!((between[1].scale.x - 1.6875).abs() < 1e-5, "{}", between[1].scale.x);
    // Looping: 2.5 s is 0.5 s into the next loop.
    let looped = pose(2.5);
    assert!(looped[1].rotation.abs_diff_eq(between[1].rotation, 1e-6));
}

#[test]
fn the_character_is_reproducible_from_its_generator() {
    // The committed file and the generator's output load to the same model (compared with a
    // tolerance, so a platform's last-bit differences in sin and cos do not matter).
    let committed = character();
    let generated = parse_model(&umbra::assets::character::character_glb(), None, "generated").unwrap();
    assert_eq!(committed.nodes.len(), generated.nodes.len());
    assert_eq!(committed.parts.len(), generated.parts.len());
    for (a, b) in committed.parts.iter().zip(&generated.parts) {
        assert_eq!(a.mesh.indices, b.mesh.indices);
        for (u, v) in a.mesh.vertices.iter().zip(&b.mesh.vertices) {
            assert!(Vec3::from(u.position).abs_diff_eq(Vec3::from(v.position), 1e-5));
        }
    }
    for t in [0.0, 0.3, 0.77] {
        for (a, b) in committed.pose(Some(0), t).iter().zip(generated.pose(Some(0), t)) {
            assert!(a.abs_diff_eq(b, 1e-5), "the committed character differs from its generator: rerun make_character");
        }
    }
    // What the issue asks of it: hips, spine, head, arms with elbows, legs with knees, a walk.
    let names: Vec<&str> = committed.nodes.iter().map(|n| n.name.as_str()).collect();
    for joint in ["hips", "spine", "head", "forearm.L", "forearm.R", "shin.L", "shin.R"] {
        assert!(names.contains(&joint), "{joint} in {names:?}");
    }
    assert_eq!(committed.clips[0].name, "walk");
}

#[test]
fn the_walk_moves_the_legs_and_loops_seamlessly() {
    let model = character();
    let foot = |t: f32| {
        let globals = model.pose(Some(0), t);
        let i = model.nodes.iter().position(|n| n.name == "foot.L").unwrap();
        globals[i].transform_point3(Vec3::ZERO)
    };
    let cycle = model.clips[0].duration;
    // A quarter cycle in, the left leg is forward; three quarters in, it is back.
    assert!(foot(cycle * 0.25).z - foot(cycle * 0.75).z > 0.5, "the left foot travels a stride");
    assert!(foot(0.0).abs_diff_eq(foot(cycle), 1e-5) && foot(0.1).abs_diff_eq(foot(cycle + 0.1), 1e-5));
}

#[test]
fn truncated_and_wrong_files_are_named_errors() {
    let glb = TestModel::new().glb();
    let err = parse_model(&glb[..glb.len() / 2], None, "half.glb").unwrap_err().to_string();
    assert!(err.starts_with("half.glb: truncated .glb"), "{err}");
    let mut magic = glb.clone();
    magic[..4].copy_from_slice(b"glTX");
    let err = parse_model(&magic, None, "magic.glb").unwrap_err().to_string();
    assert!(err.contains("magic.glb") && err.contains("not a glTF file"), "{err}");
    let err = parse_model(b"{ \"asset\": ", None, "cut.gltf").unwrap_err().to_string();
    assert!(err.contains("cut.gltf") && err.contains("does not parse"), "{err}");
    let err = load_model(Path::new("no/such/model.glb")).unwrap_err().to_string();
    assert!(err.contains("no/such/model.glb") && err.contains("cannot read"), "{err}");
}

#[test]
fn buffer_files_must_lie_beside_the_model() {
    let model = TestModel::new();
    let dir = scratch("outside");
    for uri in ["../column.bin", "/etc/hostname", "sub/../../x.bin", "file:///etc/hostname"] {
        let (text, _) = model.gltf_external(uri);
        std::fs::write(dir.join("column.gltf"), text).unwrap();
        let err = load_model(&dir.join("column.gltf")).unwrap_err().to_string();
        assert!(err.contains("not beside the model"), "{uri}: {err}");
    }
}

#[test]
fn mirrored_rigid_parts_keep_their_outside_out() {
    // The column drawn rigid (no skin) under a mirroring scale: its triangles turn round.
    let mut plain = TestModel::new();
    plain.json["nodes"][2].as_object_mut().unwrap().remove("skin");
    let mut mirrored = plain.clone();
    mirrored.json["nodes"][2]["scale"] = json!([-1.0, 1.0, 1.0]);
    let (a, b) = (load(&plain), load(&mirrored));
    for (s, t) in a.parts[0].mesh.indices.chunks(3).zip(b.parts[0].mesh.indices.chunks(3)) {
        assert_eq!([s[0], s[2], s[1]], [t[0], t[1], t[2]]);
    }
}

#[test]
fn missing_and_short_buffers_are_named_errors() {
    let model = TestModel::new();
    let dir = scratch("missing-bin");
    let (text, _) = model.gltf_external("gone.bin");
    std::fs::write(dir.join("column.gltf"), text).unwrap();
    let err = load_model(&dir.join("column.gltf")).unwrap_err().to_string();
    assert!(err.contains("column.gltf") && err.contains("buffer 0") && err.contains("gone.bin"), "{err}");
    let err = refused(|m| m.bin.truncate(100));
    assert!(err.contains("buffer 0 is short"), "{err}");
    let err = refused(|m| m.json["buffers"][0]["uri"] = json!("data:application/octet-stream;base64,@@@"));
    assert!(err.contains("not valid base64"), "{err}");
}

#[test]
fn accessors_and_indices_out_of_range_are_named_errors() {
    let err = refused(|m| m.json["accessors"][0]["count"] = json!(13));
    assert!(err.contains("POSITION") && err.contains("accessor 0 is out of range"), "{err}");
    let err = refused(|m| m.json["accessors"][1]["byteOffset"] = json!(1_000_000));
    assert!(err.contains("accessor 1 is out of range"), "{err}");
    let err = refused(|m| m.json["bufferViews"][2]["byteLength"] = json!(1_000_000));
    assert!(err.contains("buffer view 2 reaches byte 1000288, past the 1004 bytes that buffer 0 declares"), "{err}");
    let err = refused(|m| {
        let bad = m.add_shorts(&[0, 1, 99], "SCALAR");
        m.json["meshes"][0]["primitives"][0]["indices"] = json!(bad);
    });
    assert!(err.contains("index 99 is out of range: there are 12 vertices"), "{err}");
    let err = refused(|m| m.json["accessors"][0]["bufferView"] = json!(77));
    assert!(err.contains("accessors[0].bufferView names an object that does not exist"), "{err}");
}

#[test]
fn non_triangles_cycles_and_unknown_required_extensions_are_named_errors() {
    let err = refused(|m| m.json["meshes"][0]["primitives"][0]["mode"] = json!(1));
    assert!(err.contains("mesh 0 primitive 0") && err.contains("Lines") && err.contains("not triangles"), "{err}");
    let err = refused(|m| m.json["nodes"][1]["children"] = json!([0]));
    assert!(err.contains("cycle"), "{err}");
    let err = refused(|m| m.json["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]));
    assert!(err.contains("KHR_draco_mesh_compression") && err.contains("does not support"), "{err}");
}

#[test]
fn joints_out_of_range_and_missing_inverse_binds_are_named_errors() {
    let err = refused(|m| {
        let joints = m.add_shorts(&[[7u16, 1, 0, 0]; 12].concat(), "VEC4");
        m.json["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = json!(joints);
    });
    assert!(err.contains("uses joint 7, but its skin has 2 joints"), "{err}");
    let err = refused(|m| m.json["skins"][0]["joints"] = json!([0, 1, 2]));
    assert!(err.contains("skin 0 has 3 joints but its buffer holds only 2 inverse bind matrices"), "{err}");
    let err = refused(|m| m.json["skins"][0]["joints"] = json!([]));
    assert!(err.contains("skin 0 has 0 joints"), "{err}");
    // A joint index out of range with no weight moves nothing, so it is not an error.
    let mut model = TestModel::new();
    let joints = model.add_shorts(&[[0u16, 1, 9, 9]; 12].concat(), "VEC4");
    model.json["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = json!(joints);
    let skin = load(&model).parts[0].mesh.skin.clone().unwrap();
    assert!(skin.iter().all(|v| v.joints.iter().all(|&j| j < 2)), "{:?}", skin[0]);
}

#[test]
fn more_than_four_influences_keep_the_four_largest() {
    let mut model = TestModel::new();
    // A second set of influences on joint 1 for every vertex: 5..8 influences in all.
    let joints = model.add_shorts(&[[1u16, 1, 1, 1]; 12].concat(), "VEC4");
    let weights = model.add_floats(&[[0.25f32, 0.25, 0.25, 0.25]; 12].concat(), "VEC4");
    let attributes = &mut model.json["meshes"][0]["primitives"][0]["attributes"];
    attributes["JOINTS_1"] = json!(joints);
    attributes["WEIGHTS_1"] = json!(weights);
    let loaded = load(&model);
    assert!(loaded.warnings.iter().any(|w| w.contains("more than 4 joints")), "{:?}", loaded.warnings);
    for v in loaded.parts[0].mesh.skin.as_ref().unwrap() {
        assert!((v.weights.iter().sum::<f32>() - 1.0).abs() < 1e-5, "{v:?}");
        assert!(v.weights.iter().all(|&w| w >= 0.0));
    }
}

#[test]
fn weights_not_summing_to_one_are_normalized() {
    let mut model = TestModel::new();
    let weights = model.add_floats(&[[2.0f32, 2.0, 0.0, 0.0]; 12].concat(), "VEC4");
    model.json["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = json!(weights);
    let loaded = load(&model);
    assert!(
        loaded.warnings.iter().any(|w| w.starts_with("test.glb") && w.contains("normalized")),
        "{:?}",
        loaded.warnings
    );
    let skin = loaded.parts[0].mesh.skin.as_ref().unwrap();
    assert!(skin.iter().all(|v| v.weights == [0.5, 0.5, 0.0, 0.0]), "{:?}", skin[0]);
}

#[test]
fn morph_targets_are_ignored_with_a_warning() {
    let mut model = TestModel::new();
    // Offsets of a whole metre, so a loader that applied them would move every vertex.
    let offsets = model.add_floats(&[1.0; 36], "VEC3");
    model.json["meshes"][0]["primitives"][0]["targets"] = json!([{ "POSITION": offsets }]);
    model.json["meshes"][0]["weights"] = json!([0.5]);
    let loaded = load(&model);
    assert!(loaded.warnings.iter().any(|w| w.contains("morph targets are ignored")), "{:?}", loaded.warnings);
    assert_eq!(loaded.parts[0].mesh.vertices, load(&TestModel::new()).parts[0].mesh.vertices);
}

#[test]
fn missing_normals_are_made_flat() {
    let mut model = TestModel::new();
    model.json["meshes"][0]["primitives"][0]["attributes"].as_object_mut().unwrap().remove("NORMAL");
    let loaded = load(&model);
    let mesh = &loaded.parts[0].mesh;
    assert_eq!(mesh.vertices.len(), 48, "one vertex per corner of 16 triangles");
    for t in mesh.indices.chunks(3) {
        let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(mesh.vertices[t[k] as usize].position));
        let face = (b - a).cross(c - a).normalize();
        assert!(face.abs_diff_eq(Vec3::from(mesh.vertices[t[0] as usize].normal), 1e-5));
    }
    assert_eq!(mesh.skin.as_ref().map(Vec::len), Some(48), "influences follow the new vertices");
}

#[test]
fn no_corruption_of_a_real_file_panics() {
    // Every way of cutting the character short, and a few thousand single-byte corruptions of
    // it, give an error or a model, never a panic (200,000 corruptions passed when written).
    let glb = umbra::scene::CHARACTER_GLB;
    for len in (0..glb.len()).step_by(61) {
        assert!(parse_model(&glb[..len], None, "cut.glb").is_err(), "cut at {len}");
    }
    let mut state = 0x2545f4914f6cdd1du64;
    for _ in 0..4000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let mut copy = glb.to_vec();
        let at = (state >> 16) as usize % copy.len();
        // Half the time a digit of the JSON becomes another digit: an index, count or offset
        // that is still a number but points somewhere else.
        let json_end = 20 + u32::from_le_bytes([glb[12], glb[13], glb[14], glb[15]]) as usize;
        let digit = |b: u8| b.is_ascii_digit();
        match (state & 1, (20..json_end).rev().find(|&i| i <= 20 + at % (json_end - 20) && digit(copy[i]))) {
            (0, Some(i)) => copy[i] = b'0' + ((state >> 8) % 10) as u8,
            _ => copy[at] = (state >> 8) as u8,
        }
        if let Ok(model) = parse_model(&copy, None, "flipped.glb") {
            // Whatever loads must also pose without trouble.
            let globals = model.pose(Some(0), 0.4);
            for part in &model.parts {
                let _ = model.part_bounds(part, &globals, &Mat4::IDENTITY);
                let _ = part.skin.map(|s| model.joint_matrices(s, &globals));
            }
        }
    }
}

#[test]
fn interleaved_attributes_and_matrix_nodes_load() {
    // POSITION and NORMAL interleaved in one view with a 24-byte stride, as exporters often write.
    let mut model = TestModel::new();
    let plain = load(&model);
    let view = |m: &TestModel, i: usize| {
        let v = &m.json["bufferViews"][i];
        let (at, len) = (v["byteOffset"].as_u64().unwrap() as usize, v["byteLength"].as_u64().unwrap() as usize);
        m.bin[at..at + len].to_vec()
    };
    let (positions, normals) = (view(&model, 0), view(&model, 1));
    let interleaved: Vec<u8> =
        positions.chunks(12).zip(normals.chunks(12)).flat_map(|(p, n)| [p, n].concat()).collect();
    let at = model.bin.len();
    model.bin.extend(&interleaved);
    model.json["buffers"][0]["byteLength"] = json!(model.bin.len());
    let views = model.json["bufferViews"].as_array_mut().unwrap();
    views.push(json!({ "buffer": 0, "byteOffset": at, "byteLength": interleaved.len(), "byteStride": 24 }));
    let v = views.len() - 1;
    model.json["accessors"][0]["bufferView"] = json!(v);
    model.json["accessors"][1]["bufferView"] = json!(v);
    model.json["accessors"][1]["byteOffset"] = json!(12);
    // The joints hang under a node given as a matrix (a Z-up to Y-up turn and a shift), with
    // inverse binds to match; the skinned mesh's own node moves too, which must not matter.
    let turn = Mat4::from_translation(Vec3::new(3.0, 0.0, 0.0)) * Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    model.json["nodes"].as_array_mut().unwrap().push(json!({ "matrix": turn.to_cols_array(), "children": [0] }));
    model.json["scenes"][0]["nodes"] = json!([3, 2]);
    model.json["nodes"][2]["translation"] = json!([5.0, 0.0, 0.0]);
    let ibm: Vec<f32> = [0.0f32, 1.0]
        .iter()
        .flat_map(|y| (turn * Mat4::from_translation(Vec3::Y * *y)).inverse().to_cols_array())
        .collect();
    let ibm = model.add_floats(&ibm, "MAT4");
    model.json["skins"][0]["inverseBindMatrices"] = json!(ibm);
    let loaded = load(&model);
    assert_eq!(loaded.parts[0].mesh.vertices, plain.parts[0].mesh.vertices);
    let globals = loaded.pose(None, 0.0);
    let posed = skin_vertices(&loaded.parts[0].mesh, &loaded.joint_matrices(0, &globals));
    for (p, v) in posed.iter().zip(&plain.parts[0].mesh.vertices) {
        assert!(Vec3::from(p.position).abs_diff_eq(Vec3::from(v.position), 1e-5), "{p:?} vs {v:?}");
    }
}

#[test]
fn sparse_accessors_replace_the_elements_they_list() {
    // Vertices 3 and 7 of POSITION are moved by a sparse substitution over the dense data.
    let mut model = TestModel::new();
    let indices = model.add_shorts(&[3, 7], "SCALAR");
    let values = model.add_floats(&[0.5, 0.25, 0.5, -0.5, 1.75, -0.5], "VEC3");
    let view = |m: &TestModel, acc: usize| m.json["accessors"][acc]["bufferView"].clone();
    let sparse = json!({
        "count": 2,
        "indices": { "bufferView": view(&model, indices), "componentType": 5123 },
        "values": { "bufferView": view(&model, values) }
    });
    model.json["accessors"][0]["sparse"] = sparse;
    let loaded = load(&model);
    let plain = load(&TestModel::new());
    let (got, was) = (&loaded.parts[0].mesh.vertices, &plain.parts[0].mesh.vertices);
    assert_eq!(got[3].position, [0.5, 0.25, 0.5]);
    assert_eq!(got[7].position, [-0.5, 1.75, -0.5]);
    for i in (0..12).filter(|i| ![3, 7].contains(i)) {
        assert_eq!(got[i].position, was[i].position, "vertex {i} is not listed and keeps its value");
    }
    // A sparse index past the accessor's elements is a named error.
    let mut bad = model.clone();
    let past = bad.add_shorts(&[3, 12], "SCALAR");
    bad.json["accessors"][0]["sparse"]["indices"]["bufferView"] = view(&bad, past);
    let err = parse_model(&bad.glb(), None, "sparse.glb").unwrap_err().to_string();
    assert!(err.contains("sparse index 12 is past its 12 elements"), "{err}");
    // Indices out of order (or repeated) break glTF's rule, and a repeat would be ambiguous.
    for order in [[7u16, 3], [3, 3]] {
        let mut unsorted = model.clone();
        let listed = unsorted.add_shorts(&order, "SCALAR");
        unsorted.json["accessors"][0]["sparse"]["indices"]["bufferView"] = view(&unsorted, listed);
        let err = parse_model(&unsorted.glb(), None, "sparse.glb").unwrap_err().to_string();
        assert!(err.contains("glTF asks for strictly increasing indices"), "{err}");
        assert!(err.contains("sparse.glb") && err.contains("accessor 0"), "the file and the accessor: {err}");
    }
}

#[test]
fn a_node_with_a_matrix_and_a_translation_and_a_skin_listing_a_joint_twice_are_warned_of() {
    let mut m = TestModel::new();
    m.json["nodes"][1]["matrix"] = json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 2, 0, 1]);
    let model = load(&m);
    assert!(
        model.warnings.iter().any(|w| w.contains("node 1 has both a matrix and a translation")),
        "{:?}",
        model.warnings
    );
    // The matrix is what places it: 2 m up, not the translation's 1 m.
    assert_eq!(model.nodes[1].rest.translation, glam::Vec3::new(0.0, 2.0, 0.0));
    let mut m = TestModel::new();
    m.json["skins"][0]["joints"] = json!([1, 1]);
    let model = load(&m);
    assert!(model.warnings.iter().any(|w| w.contains("skin 0 lists node 1 twice")), "{:?}", model.warnings);
    assert!(load(&TestModel::new()).warnings.is_empty());
}
