//! Writes the sample's walking character, `assets/character.glb`, from the code in
//! `src/assets/character/`: run it after changing the mesh, skeleton or walk.

use std::path::Path;

fn main() -> anyhow::Result<()> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(umbra::assets::character::CHARACTER_PATH);
    let bytes = umbra::assets::character::character_glb();
    std::fs::write(&path, &bytes)?;
    let model = umbra::assets::parse_model(&bytes, None, "character.glb")?;
    let triangles: usize = model.parts.iter().map(|p| p.mesh.triangle_count()).sum();
    println!(
        "wrote {} ({} bytes): {} joints, {} parts, {triangles} triangles, clip \"{}\" of {} s",
        path.display(),
        bytes.len(),
        model.skins.first().map_or(0, |s| s.joints.len()),
        model.parts.len(),
        model.clips.first().map_or("", |c| c.name.as_str()),
        model.clips.first().map_or(0.0, |c| c.duration),
    );
    Ok(())
}
