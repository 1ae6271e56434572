//! The Adreno's own shader compiler on a machine without an Adreno: Mesa's turnip (the open
//! Vulkan driver of Qualcomm's GPUs, with ir3, its compiler) on the no-op msm kernel shim of
//! `src/freedreno/drm-shim` ("the minimum of msm in order to make shader-db work": submits do
//! nothing). `vr-ocean gpu-budget` creates the app's pipelines on it as an Adreno 650 (Quest 2)
//! and 740 (Quest 3) and reads what ir3 made of each shader (`docs/notes/gpu-cost-model.md`).
//!
//! [`ensure_turnip`] builds it once from Debian trixie's Mesa source (`apt-get source mesa`, the
//! release the Monado root's lavapipe comes from, with Debian's patches), kept and restored from
//! a tarball like the Monado root ([`crate::cache::CachedTree`]): `<cache>/turnip/` holds
//! `lib/x86_64-linux-gnu/libvulkan_freedreno.so`, its ICD manifest
//! `share/vulkan/icd.d/freedreno_icd.x86_64.json` and the shim
//! `lib/x86_64-linux-gnu/libfreedreno_noop_drm_shim.so`.
//!
//! Built on the host, not in a trixie root: the driver is loaded into the host's `vr-ocean`
//! (bookworm's glibc, which a trixie-built library would outrun). Bookworm's meson (1.0) is older
//! than Mesa 25 asks for (1.1), so meson alone comes from PyPI, pinned ([`MESON`]), in a venv
//! over Debian's Python (whose mako, yaml and packaging Mesa's generators import); every other
//! build dependency is Debian's ([`crate::setup::APT_PACKAGES`]). About 3 minutes on 2 cores.
//!
//! The shim's device table lacks the Adreno 650 ([`SHIM_A650`] adds it).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use crate::cache::{mkdir, note, remove_tree, rename, run_logged, CachedTree};
use crate::process::is_root;
use crate::{Failure, Result};

/// The Debian suite whose Mesa source is built (the Monado root's, `crate::monado::SUITE`).
const SUITE: &str = crate::monado::SUITE;

/// meson from PyPI (bookworm's 1.0.1 is older than Mesa 25's minimum, 1.1).
const MESON: &str = "meson==1.7.2";

/// Mesa's build options: the freedreno Vulkan driver and the drm-shim tools, nothing else (no
/// GL, no LLVM, no window systems).
const MESON_OPTIONS: &[&str] = &[
    "--wrap-mode=nodownload",
    "--buildtype=release",
    "-Dvulkan-drivers=freedreno",
    "-Dgallium-drivers=",
    "-Dtools=drm-shim",
    "-Dfreedreno-kmds=msm",
    "-Dplatforms=",
    "-Dglx=disabled",
    "-Degl=disabled",
    "-Dgles1=disabled",
    "-Dgles2=disabled",
    "-Dopengl=false",
    "-Dllvm=disabled",
    "-Dvideo-codecs=",
    "-Dvalgrind=disabled",
    "-Dlibunwind=disabled",
];

/// The shim's table entry this file adds after its 640-less a6xx list: the Adreno 650 of the
/// Snapdragon 865 and the XR2 Gen 1 (Quest 2). Chip id 6.5.0.2 and 1.125 MiB of GMEM as Linux's
/// msm driver lists it (`drivers/gpu/drm/msm/adreno/a6xx_catalog.c`); Mesa's device table
/// (`freedreno_devices.py`, `GPUId(650)`) gives the compiler its wave and register sizes.
pub const SHIM_A650: &str = "   {
      .gpu_id = 650,
      .chip_id = CHIPID(6, 5, 0, 2),
      .gmem_size = 1024 * 1024 + 128 * 1024,
   },
";

/// Where [`SHIM_A650`] goes: before the 660's entry.
const SHIM_ANCHOR: &str = "   {\n      .gpu_id = 660,";

/// The shim's source file.
const SHIM_SOURCE: &str = "src/freedreno/drm-shim/freedreno_noop.c";

/// Name of the stamp file inside the tree.
const STAMP: &str = "vr-ocean-stamp.txt";

/// The tree's ICD manifest (what `VK_ICD_FILENAMES` names), relative to it.
pub const ICD: &str = "share/vulkan/icd.d/freedreno_icd.x86_64.json";

/// The no-op kernel shim (`LD_PRELOAD`), relative to the tree.
pub const SHIM: &str = "lib/x86_64-linux-gnu/libfreedreno_noop_drm_shim.so";

/// What the stamp of an up-to-date tree says: the source, the build's options, the shim's
/// patch and the tree's own path (the ICD manifest names the driver by its absolute path).
fn stamp_text(prefix: &Path) -> String {
    format!(
        "vr-ocean turnip (Mesa's Adreno Vulkan driver on its no-op kernel shim), made by `cargo \
         xtask turnip` (xtask/src/turnip.rs)\nsource=debian {SUITE} mesa, with debian/patches\n\
         meson={MESON}\noptions={}\nshim patch={}\nprefix={}\n",
        MESON_OPTIONS.join(" "),
        SHIM_A650.split_whitespace().collect::<Vec<_>>().join(" "),
        prefix.display()
    )
}

/// The driver as a cached tree: `<cache>/turnip`.
fn tree() -> CachedTree {
    let name = "turnip".to_string();
    let prefix = crate::cache::cache_dir().join(&name);
    CachedTree {
        what: "turnip (the Adreno compiler)",
        stamp: stamp_text(&prefix),
        name,
        stamp_file: STAMP,
    }
}

/// Makes sure the driver is built (see the module docs); returns the tree's path.
pub fn ensure_turnip() -> Result<PathBuf> {
    let tree = tree();
    let prefix = tree.path();
    tree.ensure(|partial| build(partial, &prefix))
}

/// The `prepare` hook of the step that runs `vr-ocean gpu-budget`'s test: the tree's path in
/// `VR_OCEAN_TURNIP`. Not root and no tree yet: nothing (the test then fails under `CI=true`
/// and says it did not run otherwise).
pub fn prepare_step() -> Result<Vec<(String, String)>> {
    let tree = tree();
    let root = if is_root() {
        ensure_turnip()?
    } else if tree.read_stamp(&tree.path()).as_deref() == Some(tree.stamp.as_str()) {
        tree.path()
    } else {
        note(
            "not root: the Adreno compiler (turnip) is not built, so gpu-budget's Adreno \
             statistics are not tested (as root: cargo xtask turnip)",
        );
        return Ok(Vec::new());
    };
    Ok(vec![(
        "VR_OCEAN_TURNIP".into(),
        root.to_string_lossy().into_owned(),
    )])
}

/// Downloads, patches, builds and installs Mesa's turnip into `partial` (whose final path is
/// `prefix`).
fn build(partial: &Path, prefix: &Path) -> Result<()> {
    let work = partial.with_extension("build");
    remove_tree(&work)?;
    mkdir(&work)?;
    let start = Instant::now();
    let source = fetch_source(&work)?;
    patch_shim(&source.dir)?;
    let venv = meson_venv(&work)?;
    let path = format!(
        "{}:{}",
        venv.join("bin").display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let build_dir = work.join("build");
    let mut setup = Command::new(venv.join("bin/meson"));
    setup
        .arg("setup")
        .arg(&build_dir)
        .args(MESON_OPTIONS)
        .arg(format!("-Dprefix={}", prefix.display()))
        .current_dir(&source.dir)
        .env("PATH", &path);
    note(&format!(
        "configuring Mesa {} (log: {})",
        source.version,
        work.join("setup.log").display()
    ));
    run_logged(&mut setup, &work.join("setup.log"), "meson setup")?;
    note("building turnip and the shim (about 3 minutes on 2 cores)");
    let stage = work.join("stage");
    let mut install = Command::new("ninja");
    install
        .arg("-C")
        .arg(&build_dir)
        .arg("install")
        .env("PATH", &path)
        .env("DESTDIR", &stage);
    run_logged(&mut install, &work.join("build.log"), "ninja install")?;
    // DESTDIR puts the tree under its final path inside the stage: move its parts into place.
    let staged = stage.join(prefix.strip_prefix("/").unwrap_or(prefix));
    for entry in fs::read_dir(&staged)
        .map_err(|e| Failure::Msg(format!("cannot read {}: {e}", staged.display())))?
        .flatten()
    {
        rename(&entry.path(), &partial.join(entry.file_name()))?;
    }
    for part in [ICD, SHIM] {
        if !partial.join(part).is_file() {
            return Err(Failure::Msg(format!(
                "Mesa's install did not make {part} (log: {})",
                work.join("build.log").display()
            )));
        }
    }
    fs::write(
        partial.join("mesa-version.txt"),
        format!("{}\n", source.version),
    )
    .map_err(|e| Failure::Msg(format!("cannot write the version: {e}")))?;
    remove_tree(&work)?;
    note(&format!(
        "built turnip from Mesa {} in {:.0} s",
        source.version,
        start.elapsed().as_secs_f64()
    ));
    Ok(())
}

/// Mesa's unpacked source with Debian's patches applied, and its Debian version.
struct Source {
    dir: PathBuf,
    version: String,
}

/// `apt-get source --download-only mesa` from the suite's `deb-src`, in a private apt state
/// (the machine's own sources are left alone), then unpacked and patched with Debian's series.
fn fetch_source(work: &Path) -> Result<Source> {
    if !is_root() {
        return Err(Failure::Msg(
            "building turnip needs root for apt-get (Debian's Mesa source): run as root, e.g. \
             `sudo -E env \"PATH=$PATH\" cargo xtask turnip`"
                .into(),
        ));
    }
    let apt = work.join("apt");
    let parts = apt.join("sources.list.d");
    mkdir(&parts)?;
    mkdir(&apt.join("lists/partial"))?;
    mkdir(&apt.join("cache/archives/partial"))?;
    fs::write(
        parts.join("deb-src.sources"),
        format!(
            "Types: deb-src\nURIs: {}\nSuites: {SUITE}\nComponents: main\n\
             Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg\n",
            crate::monado::MIRROR
        ),
    )
    .map_err(|e| Failure::Msg(format!("cannot write apt's sources: {e}")))?;
    let options = [
        "-o".to_string(),
        "Dir::Etc::SourceList=/dev/null".into(),
        "-o".into(),
        format!("Dir::Etc::SourceParts={}", parts.display()),
        "-o".into(),
        format!("Dir::State::Lists={}", apt.join("lists").display()),
        "-o".into(),
        format!("Dir::Cache={}", apt.join("cache").display()),
        "-o".into(),
        "APT::Sandbox::User=root".into(),
    ];
    note(&format!("downloading Debian {SUITE}'s Mesa source"));
    let mut update = Command::new("apt-get");
    update.args(&options).args(["-q", "update"]);
    run_logged(&mut update, &work.join("apt-update.log"), "apt-get update")?;
    let src = work.join("src");
    mkdir(&src)?;
    let mut source = Command::new("apt-get");
    source
        .args(&options)
        .args(["-q", "source", "--download-only", "mesa"])
        .current_dir(&src);
    run_logged(&mut source, &work.join("apt-source.log"), "apt-get source")?;
    let files: Vec<String> = fs::read_dir(&src)
        .map_err(|e| Failure::Msg(format!("cannot read {}: {e}", src.display())))?
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    let find = |suffix: &str| {
        files
            .iter()
            .find(|f| f.starts_with("mesa_") && f.ends_with(suffix))
            .cloned()
            .ok_or_else(|| {
                Failure::Msg(format!(
                    "apt-get source mesa left no mesa_*{suffix} in {}",
                    src.display()
                ))
            })
    };
    let dsc = find(".dsc")?;
    let version = dsc["mesa_".len()..dsc.len() - ".dsc".len()].to_string();
    let upstream = version.split('-').next().unwrap_or(&version).to_string();
    for tarball in [find(".orig.tar.xz")?, find(".debian.tar.xz")?] {
        let mut tar = Command::new("tar");
        tar.arg("-xJf").arg(&tarball).current_dir(&src);
        run_logged(&mut tar, &work.join("untar.log"), "unpacking the source")?;
    }
    let dir = src.join(format!("mesa-{upstream}"));
    let series = fs::read_to_string(src.join("debian/patches/series")).unwrap_or_default();
    for patch in series
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
    {
        let file = src.join("debian/patches").join(patch);
        let input = fs::File::open(&file)
            .map_err(|e| Failure::Msg(format!("cannot open {}: {e}", file.display())))?;
        let mut cmd = Command::new("patch");
        cmd.args(["-p1", "-s", "--forward"]).current_dir(&dir);
        let log = work.join("patch.log");
        let out = fs::File::create(&log)
            .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", log.display())))?;
        let status = cmd
            .stdin(input)
            .stdout(
                out.try_clone()
                    .map_err(|e| Failure::Msg(format!("cannot reopen {}: {e}", log.display())))?,
            )
            .stderr(out)
            .status()
            .map_err(|e| Failure::Msg(format!("cannot run patch (apt-get install patch): {e}")))?;
        if !status.success() {
            return Err(Failure::Msg(format!(
                "Debian's patch {patch} does not apply to Mesa {version}: {}",
                fs::read_to_string(&log).unwrap_or_default()
            )));
        }
    }
    Ok(Source { dir, version })
}

/// Adds the Adreno 650 to the shim's device table ([`SHIM_A650`]).
fn patch_shim(source: &Path) -> Result<()> {
    let file = source.join(SHIM_SOURCE);
    let text = fs::read_to_string(&file)
        .map_err(|e| Failure::Msg(format!("cannot read {}: {e}", file.display())))?;
    let patched = add_a650(&text).ok_or_else(|| {
        Failure::Msg(format!(
            "{} has no Adreno 660 entry to put the 650 before: this Mesa's shim differs from \
             the one xtask/src/turnip.rs was written for; update SHIM_ANCHOR",
            file.display()
        ))
    })?;
    fs::write(&file, patched)
        .map_err(|e| Failure::Msg(format!("cannot write {}: {e}", file.display())))
}

/// `text` with [`SHIM_A650`] before the 660's entry; `None` when there is no such entry. A
/// table that already has a 650 is left as it is.
fn add_a650(text: &str) -> Option<String> {
    if text.contains(".gpu_id = 650,") {
        return Some(text.to_string());
    }
    let at = text.find(SHIM_ANCHOR)?;
    Some(format!("{}{SHIM_A650}{}", &text[..at], &text[at..]))
}

/// A venv over Debian's Python with [`MESON`] from PyPI.
fn meson_venv(work: &Path) -> Result<PathBuf> {
    let venv = work.join("venv");
    let python = ["/usr/bin/python3"]
        .into_iter()
        .map(PathBuf::from)
        .find(|p| p.is_file())
        .ok_or_else(|| Failure::Msg("Debian's python3 (/usr/bin/python3) is missing".into()))?;
    note(&format!(
        "installing {MESON} from PyPI into {}",
        venv.display()
    ));
    let mut make = Command::new(python);
    make.args(["-m", "venv", "--system-site-packages"])
        .arg(&venv);
    run_logged(
        &mut make,
        &work.join("venv.log"),
        "python3 -m venv (apt-get install python3-venv)",
    )?;
    let mut pip = Command::new(venv.join("bin/pip"));
    pip.args(["install", "-q", "--disable-pip-version-check", MESON]);
    run_logged(&mut pip, &work.join("pip.log"), "pip install meson")?;
    Ok(venv)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_a650_goes_before_the_660_once() {
        let table = "   {\n      .gpu_id = 618,\n   },\n   {\n      .gpu_id = 660,\n   },\n";
        let once = add_a650(table).unwrap();
        assert!(once.find(".gpu_id = 650,").unwrap() < once.find(".gpu_id = 660,").unwrap());
        assert_eq!(add_a650(&once).unwrap(), once);
        assert_eq!(add_a650("no table here"), None);
    }

    #[test]
    fn the_stamp_names_the_source_options_patch_and_path() {
        let s = stamp_text(Path::new("/cache/turnip"));
        assert!(s.contains("mesa"));
        assert!(s.contains("-Dvulkan-drivers=freedreno"));
        assert!(s.contains(".gpu_id = 650,"));
        assert!(s.contains("prefix=/cache/turnip\n"));
    }
}
