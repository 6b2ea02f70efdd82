//! glTF's metallic-roughness materials mapped to raystep's (book/scenes.md, *glTF scenes*, has the
//! table), and their textures decoded.
//!
//! With base colour c, metallic m, roughness r (each the factor times its texture's channel
//! where raystep reads one), transmission τ, index of refraction η and emission e:
//! - **Monte Carlo BSDF:** τ ≥ ½: glass of index η; else m ≥ ½: glossy (GGX) tinted by c with
//!   roughness r (a mirror below 0.03), the metallic-roughness texture's green channel as its
//!   roughness texture; else Lambert with albedo c. Metals and dielectrics are not blended: a
//!   dielectric's specular coat and a metal's colored Fresnel are left out.
//! - **Whitted's Phong:** colour c, ambient 0.1, diffuse 0.9·(1 − m·(1 − r)), specular 0.9·(1 − r),
//!   shininess 2/α² − 2 (α = r², held to 1 … 10 000: the Phong exponent whose lobe is as wide as
//!   the microfacet one, Walter et al. 2007), reflective m·(1 − r)², transparency τ, index η.
//! - **Emission** e × `KHR_materials_emissive_strength`: the surface is an area light.

use super::{GltfError, read_uri};
use crate::scene::texture::{self, Filter, TextureKind, Wrap};
use crate::scene::{BsdfKind, Material, Texture};
use glam::Vec3;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The materials and textures of one file, made as primitives ask for them.
pub(super) struct Materials<'d> {
    buffers: &'d [Vec<u8>],
    base: PathBuf,
    prefix: String,
    budget: u64,
    names: Vec<String>,
    texture_names: Vec<String>,
    /// glTF material index (None: the default material) → index in `out`.
    made: HashMap<Option<usize>, usize>,
    out: Vec<Material>,
    /// (glTF texture index, read as sRGB) → index in `textures`.
    made_textures: HashMap<(usize, bool), u32>,
    textures: Vec<Texture>,
    /// Texture features left out, each named once.
    left_out: Vec<String>,
}

impl<'d> Materials<'d> {
    pub(super) fn new(
        doc: &'d gltf::Document,
        buffers: &'d [Vec<u8>],
        base: &Path,
        prefix: &str,
        budget: u64,
    ) -> Materials<'d> {
        Materials {
            buffers,
            base: base.to_path_buf(),
            prefix: prefix.to_string(),
            budget,
            names: super::unique_names(doc.materials().map(|m| m.name()), "material"),
            texture_names: {
                let names: Vec<Option<String>> = doc
                    .textures()
                    .map(|t| t.name().map(str::to_string))
                    .collect();
                super::unique_names(names.iter().map(Option::as_deref), "texture")
            },
            made: HashMap::new(),
            out: vec![],
            made_textures: HashMap::new(),
            textures: vec![],
            left_out: vec![],
        }
    }

    /// The raystep material for a primitive's glTF material (made on first use).
    pub(super) fn material(&mut self, m: &gltf::Material) -> Result<usize, GltfError> {
        if let Some(&k) = self.made.get(&m.index()) {
            return Ok(k);
        }
        let at = m.index().map_or_else(
            || "materials (the default material)".to_string(),
            |i| format!("materials[{i}]"),
        );
        let name = match m.index() {
            Some(i) => format!("{}/{}", self.prefix, self.names[i]),
            None => format!("{}/default material", self.prefix),
        };
        let pbr = m.pbr_metallic_roughness();
        let [r, g, b, _alpha] = pbr.base_color_factor();
        let metallic = pbr.metallic_factor();
        let roughness = pbr.roughness_factor();
        let transmission = m.transmission().map_or(0.0, |t| t.transmission_factor());
        let ior = m.ior().unwrap_or(1.5);
        let strength = m.emissive_strength().unwrap_or(1.0);
        let emission = Vec3::from(m.emissive_factor()) * strength;
        let color = Vec3::new(r, g, b);
        for (field, v) in [
            ("pbrMetallicRoughness.baseColorFactor", color.min_element()),
            ("pbrMetallicRoughness.baseColorFactor", color.max_element()),
            ("pbrMetallicRoughness.metallicFactor", metallic),
            ("pbrMetallicRoughness.roughnessFactor", roughness),
            (
                "extensions.KHR_materials_transmission.transmissionFactor",
                transmission,
            ),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(GltfError::at(
                    format!("{at}.{field}"),
                    format!("must lie in [0, 1], got {v}"),
                ));
            }
        }
        if !(ior.is_finite() && ior > 0.0) {
            return Err(GltfError::at(
                format!("{at}.extensions.KHR_materials_ior.ior"),
                format!("must be positive, got {ior}"),
            ));
        }
        if !(emission.is_finite() && emission.min_element() >= 0.0) {
            return Err(GltfError::at(
                format!("{at}.emissiveFactor"),
                "must be finite and not negative (times its strength)",
            ));
        }
        let texture = match pbr.base_color_texture() {
            Some(info) => Some(self.texture(
                &info,
                true,
                &format!("{at}.pbrMetallicRoughness.baseColorTexture"),
            )?),
            None => None,
        };
        let glass = transmission >= 0.5;
        let metal = !glass && metallic >= 0.5;
        let roughness_texture = match pbr.metallic_roughness_texture() {
            Some(info) if metal => Some(self.texture(
                &info,
                false,
                &format!("{at}.pbrMetallicRoughness.metallicRoughnessTexture"),
            )?),
            Some(_) => {
                self.leave_out(
                    "a metallic-roughness texture on a material raystep reads as diffuse or glass",
                );
                None
            }
            None => None,
        };
        if m.normal_texture().is_some() {
            self.leave_out("normal textures");
        }
        if m.occlusion_texture().is_some() {
            self.leave_out("occlusion textures");
        }
        if m.emissive_texture().is_some() {
            self.leave_out("emissive textures (the emissive factor is read)");
        }
        if m.alpha_mode() != gltf::material::AlphaMode::Opaque {
            self.leave_out("alpha blending and masks (every surface is opaque)");
        }
        if m.transmission()
            .is_some_and(|t| t.transmission_texture().is_some())
        {
            self.leave_out("transmission textures");
        }
        let alpha = (roughness * roughness).max(1e-6);
        let material = Material {
            name,
            color,
            ambient: 0.1,
            diffuse: 0.9 * (1.0 - metallic * (1.0 - roughness)),
            specular: 0.9 * (1.0 - roughness),
            shininess: (2.0 / (alpha * alpha) - 2.0).clamp(1.0, 10_000.0),
            reflective: if glass {
                0.0
            } else {
                metallic * (1.0 - roughness).powi(2)
            },
            transparency: transmission,
            refractive_index: ior,
            emission,
            bsdf: Some(if glass {
                BsdfKind::Glass
            } else if metal {
                BsdfKind::Glossy
            } else {
                BsdfKind::Diffuse
            }),
            roughness,
            texture,
            roughness_texture,
        };
        self.out.push(material);
        self.made.insert(m.index(), self.out.len() - 1);
        Ok(self.out.len() - 1)
    }

    fn leave_out(&mut self, what: &str) {
        if !self.left_out.iter().any(|x| x == what) {
            self.left_out.push(what.to_string());
        }
    }

    /// The raystep texture for a glTF texture reference, decoded as colour (`srgb`) or data.
    fn texture(
        &mut self,
        info: &gltf::texture::Info,
        srgb: bool,
        at: &str,
    ) -> Result<u32, GltfError> {
        if info.tex_coord() != 0 {
            self.leave_out("texture coordinate sets other than TEXCOORD_0 (TEXCOORD_0 is used)");
        }
        let tex = info.texture();
        let key = (tex.index(), srgb);
        if let Some(&k) = self.made_textures.get(&key) {
            return Ok(k);
        }
        let image = tex.source();
        let image_at = format!("images[{}]", image.index());
        let (bytes, file) = match image.source() {
            gltf::image::Source::View { view, .. } => {
                let data = self
                    .buffers
                    .get(view.buffer().index())
                    .map_or(&[][..], Vec::as_slice);
                let end = view.offset().checked_add(view.length());
                let Some(slice) = end.and_then(|end| data.get(view.offset()..end)) else {
                    return Err(GltfError::at(
                        format!("{image_at}.bufferView"),
                        format!("bufferView {} lies outside its buffer", view.index()),
                    ));
                };
                (slice.to_vec(), format!("{} (embedded)", image_at))
            }
            gltf::image::Source::Uri { uri, .. } => {
                let bytes = read_uri(uri, &self.base, &format!("{image_at}.uri"), "image")?;
                let file = if uri.starts_with("data:") {
                    format!("{image_at} (data URI)")
                } else {
                    uri.to_string()
                };
                (bytes, file)
            }
        };
        let (w, h, texels) = texture::decode_image_as(&bytes, Path::new(&file), self.budget, srgb)
            .map_err(|m| GltfError::at(&image_at, format!("{m} (for {at})")))?;
        self.budget -= u64::from(w) * u64::from(h);
        let sampler = tex.sampler();
        use gltf::texture::{MagFilter, MinFilter, WrappingMode};
        let filter = match (sampler.min_filter(), sampler.mag_filter()) {
            (
                Some(
                    MinFilter::LinearMipmapLinear
                    | MinFilter::LinearMipmapNearest
                    | MinFilter::NearestMipmapLinear
                    | MinFilter::NearestMipmapNearest,
                ),
                _,
            ) => Filter::Trilinear,
            (_, Some(MagFilter::Nearest)) => Filter::Nearest,
            _ => Filter::Bilinear,
        };
        let wrap = |m: WrappingMode| match m {
            WrappingMode::ClampToEdge => Wrap::Clamp,
            WrappingMode::MirroredRepeat => Wrap::Mirror,
            WrappingMode::Repeat => Wrap::Repeat,
        };
        if sampler.wrap_s() != sampler.wrap_t() {
            self.leave_out("different wrap modes for u and v (u's is used for both)");
        }
        let name = format!(
            "{}/{}{}",
            self.prefix,
            self.texture_names[tex.index()],
            if srgb { "" } else { " (linear)" }
        );
        self.textures.push(Texture {
            name,
            kind: TextureKind::image(file, w, h, texels, filter, wrap(sampler.wrap_s())),
        });
        let k = self.textures.len() as u32 - 1;
        self.made_textures.insert(key, k);
        Ok(k)
    }

    /// The materials and textures made; what was left out joins `not_read`.
    pub(super) fn finish(self, not_read: &mut Vec<String>) -> (Vec<Material>, Vec<Texture>) {
        not_read.extend(self.left_out);
        (self.out, self.textures)
    }
}
