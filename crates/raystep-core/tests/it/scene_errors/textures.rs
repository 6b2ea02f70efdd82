//! Textures and texture coordinates: each mistake is named with its line, column and field.

use super::*;

/// A material that names texture "wood", and the texture table `lines` after it.
fn textured(lines: &[&'static str]) -> Vec<&'static str> {
    let mut v = vec![
        "[[material]]",       // 1
        "name = \"m\"",       // 2
        "texture = \"wood\"", // 3
    ];
    v.extend_from_slice(lines);
    v
}

#[test]
fn a_material_naming_an_unknown_texture_lists_the_known_ones() {
    let (w, e) = fail(&textured(&[
        "[[texture]]",       // 4
        "name = \"checks\"", // 5
        "checker = [4, 4]",  // 6
    ]));
    check(
        &w,
        &e,
        (3, 1),
        "material \"m\"",
        "texture",
        &["unknown texture \"wood\"", "\"checks\""],
    );
    let (w, e) = fail(&textured(&[]));
    check(
        &w,
        &e,
        (3, 1),
        "material \"m\"",
        "texture",
        &["no textures are defined"],
    );
}

#[test]
fn a_texture_is_a_checker_or_an_image_and_each_takes_its_own_fields() {
    let (w, e) = fail(&textured(&[
        "[[texture]]",          // 4
        "name = \"wood\"",      // 5
        "checker = [4, 4]",     // 6
        "image = \"wood.png\"", // 7
    ]));
    check(&w, &e, (7, 1), "texture \"wood\"", "image", &["not both"]);
    let (w, e) = fail(&textured(&["[[texture]]", "name = \"wood\""]));
    assert_at(&w, &e, 4, 1);
    assert_says(&e, &["`checker = [", "`image = "]);
    let (w, e) = fail(&textured(&[
        "[[texture]]",          // 4
        "name = \"wood\"",      // 5
        "checker = [4, 4]",     // 6
        "filter = \"nearest\"", // 7
    ]));
    check(
        &w,
        &e,
        (7, 1),
        "texture \"wood\"",
        "filter",
        &["applies to images"],
    );
    let (w, e) = fail(&textured(&[
        "[[texture]]",      // 4
        "name = \"wood\"",  // 5
        "checker = [0, 4]", // 6
    ]));
    check(
        &w,
        &e,
        (6, 1),
        "texture \"wood\"",
        "checker",
        &["1 … 1000000", "[0, 4]"],
    );
    let (w, e) = fail(&textured(&[
        "[[texture]]",                       // 4
        "name = \"wood\"",                   // 5
        "checker = [4, 4]",                  // 6
        "colors = [[1, 1, 1], [0.5, 2, 0]]", // 7: 2 is not a reflectance
    ]));
    check(&w, &e, (7, 1), "texture \"wood\"", "colors", &["[0, 1]"]);
    let (w, e) = fail(&textured(&[
        "[[texture]]",          // 4
        "name = \"wood\"",      // 5
        "checker = [4, 4]",     // 6
        "colors = [[1, 1, 1]]", // 7: one colour
    ]));
    assert_at(&w, &e, 7, 10);
    assert_says(&e, &["2 colours", "1 values"]);
    let (w, e) = fail(&textured(&[
        "[[texture]]",      // 4
        "name = \"wood\"",  // 5
        "checker = [4, 4]", // 6
        "[[texture]]",      // 7
        "name = \"wood\"",  // 8
        "checker = [2, 2]", // 9
    ]));
    check(
        &w,
        &e,
        (8, 1),
        "texture \"wood\"",
        "name",
        &["already defined"],
    );
}

#[test]
fn an_image_that_is_missing_unreadable_or_oddly_filtered_is_named() {
    let (w, e) = fail(&textured(&[
        "[[texture]]",          // 4
        "name = \"wood\"",      // 5
        "image = \"wood.png\"", // 6
    ]));
    check(
        &w,
        &e,
        (6, 1),
        "texture \"wood\"",
        "image",
        &["wood.png", "does not exist"],
    );
    let (w, e) = fail_with(
        &textured(&["[[texture]]", "name = \"wood\"", "image = \"wood.png\""]),
        &[("wood.png", "this is not a picture")],
    );
    check(
        &w,
        &e,
        (6, 1),
        "texture \"wood\"",
        "image",
        &["cannot read image", "wood.png", "PNG and JPEG"],
    );
    // A real 1 × 1 PNG with a filter that does not exist.
    let w = write(
        &textured(&[
            "[[texture]]",              // 4
            "name = \"wood\"",          // 5
            "image = \"wood.png\"",     // 6
            "filter = \"anisotropic\"", // 7
        ]),
        &[],
    );
    image::RgbImage::from_pixel(1, 1, image::Rgb([255, 0, 0]))
        .save(w.path.parent().unwrap().join("wood.png"))
        .unwrap();
    let e = load_file(&w.path).unwrap_err();
    check(
        &w,
        &e,
        (7, 1),
        "texture \"wood\"",
        "filter",
        &[
            "\"anisotropic\"",
            "\"nearest\"",
            "\"bilinear\"",
            "\"trilinear\"",
        ],
    );
}

#[test]
fn texture_coordinates_must_be_three_pairs_of_finite_numbers() {
    let (w, e) = fail(&[
        "[[triangle]]",                                 // 1
        "name = \"t\"",                                 // 2
        "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]", // 3
        "uvs = [[0, 0], [1, 0]]",                       // 4: two, not three
    ]);
    assert_at(&w, &e, 4, 7);
    assert_says(&e, &["3 texture coordinates", "2 values"]);
    let (w, e) = fail(&[
        "[[triangle]]",                                 // 1
        "name = \"t\"",                                 // 2
        "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]", // 3
        "uvs = [[0, 0], [1, 0, 0], [0, 1]]",            // 4: three numbers in one
    ]);
    assert_at(&w, &e, 4, 7);
    assert_says(&e, &["2 numbers [u, v] in vertex 2"]);
    let (w, e) = fail(&[
        "[[triangle]]",                                 // 1
        "name = \"t\"",                                 // 2
        "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]", // 3
        "uvs = [[0, 0], [1, nan], [0, 1]]",             // 4: not finite
    ]);
    check(&w, &e, (4, 1), "triangle \"t\"", "uvs", &["finite"]);
}

#[test]
fn obj_texture_coordinate_that_is_not_finite_names_its_line() {
    // Line 5 is the second vt, (nan, 0).
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt nan 0\nvt 0 1\nf 1/1 2/2 3/3\n";
    let (w, e) = fail_with(&mesh_scene(), &[("bad.obj", obj)]);
    check(
        &w,
        &e,
        (3, 1),
        "mesh \"teapot\"",
        "obj",
        &["texture coordinate 2", "finite"],
    );
    says_obj_line(&e, 5);
}

/// CRC-32 (ISO 3309, as PNG uses it), for the hand-made PNG below.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xffff_ffffu32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A PNG of a few dozen bytes whose header claims `w` × `h` RGB texels (its pixel data is one
/// empty zlib stream: a decoder that believed the header would allocate w·h·3 bytes first).
fn png_claiming(w: u32, h: u32) -> Vec<u8> {
    let chunk = |kind: &[u8], data: &[u8]| {
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        let mut out = (data.len() as u32).to_be_bytes().to_vec();
        out.extend_from_slice(&body);
        out.extend_from_slice(&crc32(&body).to_be_bytes());
        out
    };
    let mut ihdr = w.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.extend(chunk(b"IHDR", &ihdr));
    png.extend(chunk(
        b"IDAT",
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    ));
    png.extend(chunk(b"IEND", &[]));
    png
}

#[test]
fn an_image_claiming_a_huge_size_is_refused_by_its_header() {
    let w = write(
        &textured(&["[[texture]]", "name = \"wood\"", "image = \"wood.png\""]),
        &[],
    );
    let png = w.path.parent().unwrap().join("wood.png");
    // 100 000 × 100 000 texels: 30 GB of RGB, refused in a moment.
    std::fs::write(&png, png_claiming(100_000, 100_000)).unwrap();
    let start = std::time::Instant::now();
    let e = load_file(&w.path).unwrap_err();
    check(
        &w,
        &e,
        (6, 1),
        "texture \"wood\"",
        "image",
        &["100000 × 100000", "2048 × 2048", "smaller"],
    );
    assert!(start.elapsed().as_secs() < 5, "{:?}", start.elapsed());
    // Within the budget but with no pixel data: a clean error, not a panic.
    std::fs::write(&png, png_claiming(64, 64)).unwrap();
    let e = load_file(&w.path).unwrap_err();
    check(
        &w,
        &e,
        (6, 1),
        "texture \"wood\"",
        "image",
        &["cannot read image"],
    );
}
