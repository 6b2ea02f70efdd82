//! `raystep examples`: the scenes, lessons and exercise sheets built into raystep — listed, or
//! written out to a folder to read and edit.

use std::path::PathBuf;

/// Arguments of `raystep examples`.
#[derive(Debug, clap::Args)]
pub struct ExamplesArgs {
    /// Write every built-in scene, lesson and sheet under this folder (DIR/scenes, DIR/lessons),
    /// keeping their relative paths so the lessons' links and the sheets' scenes still resolve.
    #[arg(long, value_name = "DIR")]
    pub write: Option<PathBuf>,
    /// Replace files that already exist (without it, nothing is written if any would be).
    #[arg(long, requires = "write")]
    pub force: bool,
}

/// Lists the built-in files, or writes them out and names every file written.
pub fn run(args: &ExamplesArgs) -> Result<(), String> {
    let Some(dir) = &args.write else {
        let mut out = String::from(
            "Built into raystep (any command that takes a scene also takes a built-in scene's name, \
             e.g. `raystep render cornell -o cornell.png`):\n\nscenes:\n",
        );
        for n in crate::assets::scene_names() {
            out += &format!("  {n}\n");
        }
        out += "\nfiles (`raystep examples --write DIR` writes them under DIR):\n";
        for a in crate::assets::ASSETS {
            out += &format!("  {} ({} bytes)\n", a.path, a.bytes.len());
        }
        return super::emit(&out);
    };
    let written = crate::assets::write_examples(dir, args.force)?;
    let mut out = String::new();
    for p in &written {
        out += &format!("wrote {}\n", super::full_path(p));
    }
    out += &format!("{} files written\n", written.len());
    super::emit(&out)
}
