//! The `[[texture]]` tables: a checker's squares and colours, or an image read and decoded.

use super::*;

impl Ctx<'_> {
    /// The `[[texture]]` tables, in file order: a checker's squares and colours, or an image
    /// read (relative to the scene file) and decoded to linear texels.
    pub(super) fn textures(
        &self,
        f: &SceneFile,
        base: Option<&Path>,
    ) -> Result<Vec<Texture>, SceneError> {
        let mut out: Vec<Texture> = vec![];
        let mut budget = texture::MAX_TEXELS;
        for (i, t) in f.texture.iter().enumerate() {
            let d = t.get_ref();
            let name = d.name.clone().unwrap_or_else(|| format!("texture {i}"));
            let loc = self.loc(format!("texture \"{name}\""), t);
            if out.iter().any(|x| x.name == name) {
                return Err(loc.err(
                    "name",
                    format!("a texture named \"{name}\" is already defined"),
                ));
            }
            let kind = match (&d.checker, &d.image) {
                (Some(_), Some(_)) => {
                    return Err(loc.err(
                        "image",
                        "give either `checker` (a checkerboard) or `image` (a file), not both",
                    ));
                }
                (None, None) => {
                    return Err(loc.err(
                        "",
                        "a texture needs `checker = [squares across u, squares across v]` or `image = \"file.png\"`",
                    ));
                }
                (Some(squares), None) => {
                    for (field, given) in [("filter", &d.filter), ("wrap", &d.wrap)] {
                        if given.is_some() {
                            return Err(loc.err(
                                field,
                                format!("`{field}` applies to images; a checker is computed exactly at each point"),
                            ));
                        }
                    }
                    if squares.iter().any(|&s| s == 0 || s > 1_000_000) {
                        return Err(loc.err(
                            "checker",
                            format!(
                                "squares across u and v must lie in 1 … 1000000, got {squares:?}"
                            ),
                        ));
                    }
                    let colors = d.colors.unwrap_or([[0.9; 3], [0.15; 3]]);
                    TextureKind::Checker {
                        squares: *squares,
                        colors: [
                            loc.unit_color("colors", colors[0])?,
                            loc.unit_color("colors", colors[1])?,
                        ],
                    }
                }
                (None, Some(file)) => {
                    if d.colors.is_some() {
                        return Err(
                            loc.err("colors", "`colors` go with `checker`; an image has its own")
                        );
                    }
                    let path = base.map_or_else(|| Path::new(file).to_path_buf(), |b| b.join(file));
                    let bytes =
                        crate::io::read_input(&path, texture::MAX_IMAGE_BYTES, "image file")
                            .map_err(|e| {
                                loc.err(
                                    "image",
                                    if e.kind() == std::io::ErrorKind::NotFound {
                                        format!("image file {} does not exist", path.display())
                                    } else {
                                        format!("cannot read image file {}: {e}", path.display())
                                    },
                                )
                            })?;
                    let (width, height, texels) = texture::decode_image(&bytes, &path, budget)
                        .map_err(|m| loc.err("image", m))?;
                    budget -= u64::from(width) * u64::from(height);
                    let filter = d
                        .filter
                        .as_deref()
                        .map(|x| loc.choice("filter", x))
                        .transpose()?
                        .unwrap_or_default();
                    let wrap = d
                        .wrap
                        .as_deref()
                        .map(|x| loc.choice("wrap", x))
                        .transpose()?
                        .unwrap_or_default();
                    TextureKind::image(file.clone(), width, height, texels, filter, wrap)
                }
            };
            out.push(Texture { name, kind });
        }
        Ok(out)
    }
}
