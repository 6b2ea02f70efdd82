//! Every number a lesson quotes is printed by the command beside it, at the precision written;
//! and every shell block of the lessons runs (`shell_blocks.rs`).

use super::*;

#[test]
fn every_quoted_number_is_printed_by_the_command_beside_it_and_every_block_runs() {
    let mut runner = Runner::new();
    let mut problems = vec![];
    let mut checked = 0;
    for p in lesson_files() {
        let text = read(&p);
        let name = file_name(&p);
        let n = claims(&text).len();
        // Every lesson quotes what its commands print (lesson 11 the fewest: 2 numbers).
        eprintln!("{name}: {n} quoted numbers checked");
        assert!(n >= 2, "{name}: only {n} quoted numbers are checked");
        checked += n;
        problems.extend(stale_numbers(&text, &name, &mut runner));
    }
    // Then every shell block of the lessons and the starter kit's README, with the same runner:
    // a command that printed a number does not run twice.
    let (mut ran, mut marked) = (0, 0);
    let starter = lessons_dir().join("starter").join("README.md");
    for p in markdown_files().into_iter().chain([starter]) {
        let name = p.strip_prefix(root()).unwrap_or(&p).display().to_string();
        let (more, r, m) = shell_blocks::unrun_blocks(&read(&p), &name, &mut runner);
        problems.extend(more);
        (ran, marked) = (ran + r, marked + m);
    }
    eprintln!("{ran} shell blocks ran, {marked} marked `not run`");
    assert!(
        problems.is_empty(),
        "{} quoted numbers are not what their commands print, or shell blocks do not run (see \
         lessons/README.md, \"Quoted numbers\"):\n{}",
        problems.len(),
        problems.join("\n")
    );
    // The convention reaches the lessons: most of their numbers are checked.
    assert!(checked >= 140, "only {checked} numbers were checked");
    assert!(ran >= 50, "only {ran} shell blocks ran");
    eprintln!("{checked} quoted numbers checked");
}

#[test]
fn numbers_are_read_as_written() {
    let n = numbers_in(
        "t = −7.8414445e−07, Q = (0.5, -2, 3), E1 and D0 = 4.0, pbrt-v4, 1.2.3, 41.8°, \
         0.5863… and ≈ 46.9°, trace 168.4 ms, 1e-6",
    );
    let texts: Vec<&str> = n.iter().map(|x| x.text.as_str()).collect();
    assert_eq!(
        texts,
        [
            "−7.8414445e−07",
            "0.5",
            "-2",
            "3",
            "4.0",
            "41.8",
            "0.5863",
            "46.9",
            "168.4",
            "1e-6"
        ]
    );
    assert!((n[0].value - -7.8414445e-7).abs() < 1e-20, "{}", n[0].value);
    assert!((n[0].ulp - 1e-14).abs() < 1e-20);
    assert!(n[0].decimal && n[1].decimal && !n[2].decimal);
    assert!(n[6].cut && n[7].approx && n[8].timing);
    assert!(!n[5].cut && !n[5].approx && !n[5].timing);
    assert!(n[9].decimal && n[9].value == 1e-6);
}

#[test]
fn a_quoted_number_matches_at_the_precision_it_is_written() {
    let q = |s: &str| numbers_in(s).remove(0);
    // Rounded: 5.479765 is not 5.479516; 2.73 is 2.7312; a full quote is exact.
    assert!(!quotes(&q("5.479765"), 5.479516));
    assert!(quotes(&q("2.73"), 2.7312));
    assert!(!quotes(&q("2.73"), 2.7362));
    assert!(quotes(&q("−0.0017258584"), -0.0017258584));
    assert!(!quotes(&q("0.0017258584"), -0.0017258584));
    assert!(quotes(&q("2.842413e−09"), 2.842413e-9));
    assert!(!quotes(&q("2.842413e−09"), 2.842413e-8));
    // Cut: 0.5863… is 0.58639 but not 0.58629.
    assert!(quotes(&q("0.5863…"), 0.58639));
    assert!(!quotes(&q("0.5863…"), 0.58629));
}

/// The check catches what issue 37 found: lesson 6's grid paragraph quoting the BVH's t_near
/// (5.479765) for the grid cell's entry, where `--accel grid` prints 5.479516.
#[test]
fn a_stale_number_is_caught_and_a_fresh_one_passes() {
    let mut runner = Runner::new();
    let lesson = |t_enter: &str| {
        format!(
            "# 6.\n\n```sh\nraystep trace scenes/triangles.toml --pixel 80,130 --accel grid\n```\n\n\
             - The ray enters cell (7, 0, 0) at t = {t_enter} and leaves at t = 6.1018186.\n"
        )
    };
    let stale = stale_numbers(&lesson("5.479765"), "stale.md", &mut runner);
    assert_eq!(stale.len(), 1, "{stale:?}");
    assert!(
        stale[0].starts_with("stale.md:7: 5.479765: not printed by raystep trace"),
        "{stale:?}"
    );
    assert!(stale_numbers(&lesson("5.479516"), "fresh.md", &mut runner).is_empty());
    // A number with no command before it is reported, and a marked paragraph is not checked.
    let orphan = stale_numbers("Q is 0.25 long.\n", "o.md", &mut runner);
    assert!(
        orphan[0].contains("no command it could come from"),
        "{orphan:?}"
    );
    assert!(
        stale_numbers(
            "Q is 0.25 long. <!-- not checked: by hand -->\n",
            "o.md",
            &mut runner
        )
        .is_empty()
    );
    // A `# comment` in a sh block is checked against its own line.
    let comment = "```sh\nraystep intersect sphere --center 0,0,0 --radius 1 --origin 0,0,-5 --dir 0,0,1   # t = 4.5\n```\n";
    assert_eq!(stale_numbers(comment, "c.md", &mut runner).len(), 1);
}
