//! `cargo xtask apk-check`: CI's proof of the APK without the NDK or a headset.
//!
//! Runs `cargo xtask apk` itself (this binary) in the ways that matter and checks what comes
//! out:
//! 1. the user build with no NDK/SDK fails, naming each missing tool and where it comes from;
//! 2. `--verify-without-ndk` with no loader builds an APK without `libopenxr_loader.so` and
//!    says loudly that it cannot run;
//! 3. a missing or non-arm64 `--openxr-loader` fails clearly;
//! 4. a placeholder arm64 loader, given as a `.so` and inside an AAR, is packaged byte for
//!    byte as `lib/arm64-v8a/libopenxr_loader.so`;
//! 5. that APK: `apksigner verify` (v2 or v3 scheme, one signer), `aapt dump badging` (launchable NativeActivity,
//!    native-code arm64-v8a only, SDK 29/34, the features and permissions), `aapt dump
//!    xmltree` of the manifest (the intent categories, meta-data, `<queries>`,
//!    `<uses-native-library>`, launch mode, orientation), `llvm-readelf` of the packaged
//!    `libvr_ocean.so` (AArch64 shared object with SONAME, exports `ANativeActivity_onCreate`,
//!    NEEDs only system libraries, no text relocations), native libraries stored uncompressed,
//!    and `zipalign -c -p 4`.
//!
//! The checks of tool output are pure functions ([`check_badging`], [`check_manifest`],
//! [`check_elf`], [`check_listing`]) with unit tests that feed them wrong output.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::apk::{apk_path, target_dir, ACTIVITY, MIN_API, PACKAGE};
use crate::{android_stubs, banner, say, Failure, Result};

/// The system libraries `libvr_ocean.so` may need (Vulkan and the OpenXR loader are opened
/// with dlopen at run time).
pub const ALLOWED_NEEDED: &[&str] = &[
    "libc.so",
    "libm.so",
    "libdl.so",
    "liblog.so",
    "libandroid.so",
    // AAudio, the sound's output (cpal's Android backend), public since API 26.
    "libaaudio.so",
];

/// Intent categories the activity must have.
pub const CATEGORIES: &[&str] = &[
    "android.intent.category.LAUNCHER",
    "com.oculus.intent.category.VR",
    "org.khronos.openxr.intent.category.IMMERSIVE_HMD",
];

/// Quest devices the app declares.
pub const SUPPORTED_DEVICES: &str = "quest2|questpro|quest3|quest3s";

/// The native library members of the APK.
const LIB: &str = "lib/arm64-v8a/libvr_ocean.so";
const LOADER: &str = "lib/arm64-v8a/libopenxr_loader.so";

/// Output and status of one `xtask apk` run.
struct Run {
    ok: bool,
    text: String,
}

/// Runs this xtask binary with `args` (and `env_remove`), echoing its output.
fn xtask(args: &[&str], env_remove: &[&str]) -> Result<Run> {
    let exe = std::env::current_exe()
        .map_err(|e| Failure::Msg(format!("cannot find the xtask binary: {e}")))?;
    let mut cmd = Command::new(exe);
    cmd.args(args);
    for var in env_remove {
        cmd.env_remove(var);
    }
    say(&format!("running: xtask {}", args.join(" ")));
    let out = cmd
        .output()
        .map_err(|e| Failure::Msg(format!("cannot run xtask {}: {e}", args.join(" "))))?;
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    for line in text.lines() {
        println!("    | {line}");
    }
    Ok(Run {
        ok: out.status.success(),
        text,
    })
}

/// Collects failed expectations; the step fails if any.
#[derive(Default)]
struct Verdict {
    problems: Vec<String>,
    passed: usize,
}

impl Verdict {
    fn expect(&mut self, ok: bool, what: &str) {
        if ok {
            self.passed += 1;
            say(&format!("ok: {what}"));
        } else {
            say(&format!("FAILED: {what}"));
            self.problems.push(what.to_string());
        }
    }

    fn all(&mut self, what: &str, problems: Vec<String>) {
        let ok = problems.is_empty();
        for p in problems {
            say(&format!("  problem: {p}"));
            self.problems.push(format!("{what}: {p}"));
        }
        if ok {
            self.passed += 1;
            say(&format!("ok: {what}"));
        }
    }
}

/// Output of a tool that must succeed.
fn tool_output(cmd: &mut Command) -> Result<String> {
    crate::capture(cmd)
}

/// Output of a tool as bytes.
fn tool_bytes(cmd: &mut Command) -> Result<Vec<u8>> {
    let out = cmd
        .output()
        .map_err(|e| Failure::Msg(format!("cannot run {:?}: {e}", cmd.get_program())))?;
    if !out.status.success() {
        return Err(Failure::Msg(format!(
            "{:?} failed: {}",
            cmd.get_program(),
            String::from_utf8_lossy(&out.stderr)
        )));
    }
    Ok(out.stdout)
}

/// `cargo xtask apk-check`.
pub fn cmd_apk_check() -> Result<()> {
    let start = std::time::Instant::now();
    let target = target_dir()?;
    let work = target.join("apk-check");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", work.display())))?;
    let apk = apk_path(&target, false, true);
    let mut v = Verdict::default();

    banner("apk-check 1/5: the user build without NDK and SDK names what is missing");
    let r = xtask(
        &["apk"],
        &[
            "ANDROID_NDK_HOME",
            "ANDROID_NDK_ROOT",
            "ANDROID_HOME",
            "ANDROID_SDK_ROOT",
        ],
    )?;
    v.expect(!r.ok, "`xtask apk` without NDK/SDK fails");
    v.expect(
        r.text.contains("needs tools that are missing")
            && r.text.contains("ANDROID_NDK_HOME (the Android NDK")
            && r.text.contains("ANDROID_HOME or ANDROID_SDK_ROOT")
            && r.text.contains("developer.android.com/ndk")
            && r.text.contains("sdkmanager"),
        "its message names the NDK and the SDK and where they come from",
    );

    banner("apk-check 2/5: --verify-without-ndk without a loader");
    let r = xtask(&["apk", "--verify-without-ndk"], &[])?;
    v.expect(r.ok, "`xtask apk --verify-without-ndk` builds an APK");
    v.expect(
        r.text.contains("WARNING: this APK has NO OpenXR loader")
            && r.text.contains("cannot run on a headset")
            && r.text.contains("--openxr-loader")
            && r.text.contains("openxr_loader_for_android"),
        "it says loudly that the APK has no OpenXR loader, and how to give one",
    );
    if r.ok {
        let listing = tool_output(Command::new("aapt").args(["list", "-v"]).arg(&apk))?;
        v.all(
            "APK without loader: members",
            check_listing(&listing, false),
        );
    }

    banner("apk-check 3/5: a bad --openxr-loader is refused");
    let nowhere = work.join("nowhere/openxr_loader_for_android.aar");
    let r = xtask(
        &[
            "apk",
            "--verify-without-ndk",
            "--openxr-loader",
            &nowhere.display().to_string(),
        ],
        &[],
    )?;
    v.expect(
        !r.ok
            && r.text
                .contains(&format!("{}: no such file", nowhere.display())),
        "a missing loader file fails, naming it",
    );
    let text_file = work.join("libopenxr_loader.so.txt");
    write(&text_file, b"not a library")?;
    let r = xtask(
        &[
            "apk",
            "--verify-without-ndk",
            "--openxr-loader",
            &text_file.display().to_string(),
        ],
        &[],
    )?;
    v.expect(
        !r.ok && r.text.contains("is not an arm64 shared library"),
        "a loader that is not an arm64 .so fails, saying so",
    );

    banner("apk-check 4/5: a placeholder loader (.so, then inside an AAR) is packaged");
    let fake = fake_loader(&work)?;
    let fake_bytes = std::fs::read(&fake)
        .map_err(|e| Failure::Msg(format!("cannot read {}: {e}", fake.display())))?;
    let aar = fake_aar(&work, &fake)?;
    for given in [&fake, &aar] {
        let r = xtask(
            &[
                "apk",
                "--verify-without-ndk",
                "--openxr-loader",
                &given.display().to_string(),
            ],
            &[],
        )?;
        let name = given.file_name().unwrap_or_default().to_string_lossy();
        v.expect(
            r.ok && !r.text.contains("WARNING: this APK has NO OpenXR loader"),
            &format!("--openxr-loader {name}: builds, without the warning"),
        );
        if r.ok {
            let packaged = tool_bytes(Command::new("unzip").arg("-p").arg(&apk).arg(LOADER))?;
            v.expect(
                packaged == fake_bytes,
                &format!("--openxr-loader {name}: {LOADER} is the given loader, byte for byte"),
            );
        }
    }

    banner("apk-check 5/5: the APK (with the placeholder loader)");
    let signed = Command::new("apksigner")
        .args(["verify", "--verbose"])
        .arg(&apk)
        .output()
        .map_err(|e| Failure::Msg(format!("cannot run apksigner: {e}")))?;
    let signed_text = String::from_utf8_lossy(&signed.stdout);
    print_indented(&signed_text);
    v.expect(signed.status.success(), "apksigner verify succeeds");
    v.all("apksigner verify --verbose", check_apksigner(&signed_text));
    let listing = tool_output(Command::new("aapt").args(["list", "-v"]).arg(&apk))?;
    v.all("APK members", check_listing(&listing, true));
    let badging = tool_output(Command::new("aapt").args(["dump", "badging"]).arg(&apk))?;
    print_indented(&badging);
    v.all("aapt dump badging", check_badging(&badging));
    let tree = tool_output(
        Command::new("aapt")
            .args(["dump", "xmltree"])
            .arg(&apk)
            .arg("AndroidManifest.xml"),
    )?;
    v.all(
        "aapt dump xmltree AndroidManifest.xml",
        check_manifest(&tree),
    );
    let so = work.join("libvr_ocean.so");
    write(
        &so,
        &tool_bytes(Command::new("unzip").arg("-p").arg(&apk).arg(LIB))?,
    )?;
    let elf = tool_output(
        Command::new("llvm-readelf")
            .args(["--file-header", "--dynamic-table", "--dyn-syms", "--wide"])
            .arg(&so),
    )?;
    let needed = elf
        .lines()
        .filter(|l| l.contains("(NEEDED)") || l.contains("(SONAME)"))
        .map(str::trim)
        .collect::<Vec<_>>()
        .join("\n");
    print_indented(&needed);
    v.all("llvm-readelf libvr_ocean.so", check_elf(&elf));
    let aligned = Command::new("zipalign")
        .args(["-c", "-p", "4"])
        .arg(&apk)
        .status()
        .map_err(|e| Failure::Msg(format!("cannot run zipalign: {e}")))?;
    v.expect(aligned.success(), "zipalign -c -p 4");

    say(&format!(
        "apk-check: {} checks passed, {} failed, in {:.1}s; APK {} ({:.1} MiB)",
        v.passed,
        v.problems.len(),
        start.elapsed().as_secs_f64(),
        apk.display(),
        std::fs::metadata(&apk).map(|m| m.len()).unwrap_or(0) as f64 / (1 << 20) as f64
    ));
    if v.problems.is_empty() {
        Ok(())
    } else {
        Err(Failure::Msg(format!(
            "apk-check failed:\n  - {}",
            v.problems.join("\n  - ")
        )))
    }
}

fn print_indented(text: &str) {
    for line in text.lines() {
        println!("    | {line}");
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes)
        .map_err(|e| Failure::Msg(format!("cannot write {}: {e}", path.display())))
}

/// A placeholder `libopenxr_loader.so`: an arm64 shared object with the loader's entry
/// points as empty functions (for packaging checks only; it does nothing).
fn fake_loader(work: &Path) -> Result<PathBuf> {
    let dir = work.join("fake-loader");
    std::fs::create_dir_all(&dir)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", dir.display())))?;
    let asm = dir.join("loader.S");
    let mut text = String::from("// Placeholder OpenXR loader for apk-check.\n");
    for f in [
        "xrGetInstanceProcAddr",
        "xrInitializeLoaderKHR",
        "xrCreateInstance",
    ] {
        text.push_str(&format!(
            ".text\n.globl {f}\n.type {f}, %function\n{f}:\nret\n"
        ));
    }
    write(&asm, text.as_bytes())?;
    let so = dir.join("libopenxr_loader.so");
    android_stubs::link_shared(MIN_API, &asm, None, "libopenxr_loader.so", &so)?;
    Ok(so)
}

/// A placeholder AAR holding `so` where the Khronos AAR has its arm64 loader.
fn fake_aar(work: &Path, so: &Path) -> Result<PathBuf> {
    let root = work.join("fake-aar");
    let member = root.join(crate::openxr_loader::AAR_MEMBER);
    if let Some(dir) = member.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", dir.display())))?;
    }
    std::fs::copy(so, &member)
        .map_err(|e| Failure::Msg(format!("cannot copy to {}: {e}", member.display())))?;
    write(
        &root.join("AndroidManifest.xml"),
        b"<manifest package=\"org.khronos.openxr.openxr_loader_for_android\"/>\n",
    )?;
    let aar = work.join("openxr_loader_for_android-placeholder.aar");
    crate::capture(
        Command::new("zip")
            .args(["-q", "-r"])
            .arg(&aar)
            .args(["AndroidManifest.xml", "prefab"])
            .current_dir(&root),
    )?;
    Ok(aar)
}

// ---------------------------------------------------------------------------------------------
// Checks of tool output (pure).

/// `aapt list -v`: the native libraries are there (the loader only when `loader`), stored
/// uncompressed, and nothing else sits under `lib/`.
pub fn check_listing(listing: &str, loader: bool) -> Vec<String> {
    let mut problems = Vec::new();
    let members: Vec<(&str, &str)> = listing
        .lines()
        .filter_map(|l| {
            let cols: Vec<&str> = l.split_whitespace().collect();
            (cols.len() >= 9 && cols[0].parse::<u64>().is_ok())
                .then(|| (cols[1], cols[cols.len() - 1]))
        })
        .collect();
    let mut expect = vec![LIB];
    if loader {
        expect.push(LOADER);
    }
    for want in &expect {
        match members.iter().find(|(_, name)| name == want) {
            None => problems.push(format!("{want} is missing")),
            Some((method, _)) if *method != "Stored" => {
                problems.push(format!("{want} is {method}, not Stored (uncompressed)"))
            }
            Some(_) => {}
        }
    }
    for (_, name) in &members {
        if name.starts_with("lib/") && !expect.contains(name) {
            problems.push(format!("unexpected {name}"));
        }
    }
    for must in ["AndroidManifest.xml", "resources.arsc"] {
        if !members.iter().any(|(_, n)| *n == must) {
            problems.push(format!("{must} is missing"));
        }
    }
    problems
}

/// `apksigner verify --verbose`: verified with an APK signature scheme Android 10 checks (v2
/// or v3; minSdk 29 needs no v1 JAR signature).
pub fn check_apksigner(text: &str) -> Vec<String> {
    let lines: Vec<&str> = text.lines().map(str::trim).collect();
    let mut p = Vec::new();
    if lines.first() != Some(&"Verifies") {
        p.push("apksigner does not say `Verifies`".into());
    }
    let scheme = |v: &str| {
        lines
            .iter()
            .any(|l| l.starts_with(&format!("Verified using {v} scheme")) && l.ends_with(": true"))
    };
    if !scheme("v2") && !scheme("v3") {
        p.push("not verified with the v2 or v3 scheme".into());
    }
    if !lines.contains(&"Number of signers: 1") {
        p.push("not exactly one signer".into());
    }
    p
}

/// `aapt dump badging`: what Quest's installer and launcher read.
pub fn check_badging(text: &str) -> Vec<String> {
    let lines: Vec<&str> = text.lines().map(str::trim_end).collect();
    let mut problems = Vec::new();
    let has_prefix = |p: &str| lines.iter().any(|l| l.starts_with(p));
    let has_line = |p: &str| lines.contains(&p);
    for (ok, what) in [
        (
            has_prefix(&format!("package: name='{PACKAGE}'")),
            format!("package {PACKAGE}"),
        ),
        (has_line("sdkVersion:'29'"), "minSdkVersion 29".into()),
        (
            has_line("targetSdkVersion:'34'"),
            "targetSdkVersion 34".into(),
        ),
        (
            has_prefix(&format!("launchable-activity: name='{ACTIVITY}'")),
            format!("launchable activity {ACTIVITY}"),
        ),
        (
            has_line("native-code: 'arm64-v8a'"),
            "native-code 'arm64-v8a' (and no other ABI)".into(),
        ),
        (
            has_line("  uses-feature: name='android.hardware.vr.headtracking' version='1'"),
            "required feature android.hardware.vr.headtracking".into(),
        ),
        (
            lines
                .iter()
                .any(|l| l.starts_with("  uses-feature: name='android.hardware.vulkan.level'")),
            "required feature android.hardware.vulkan.level".into(),
        ),
        (
            has_line("uses-permission: name='org.khronos.openxr.permission.OPENXR'"),
            "permission org.khronos.openxr.permission.OPENXR".into(),
        ),
        (
            has_line("uses-permission: name='org.khronos.openxr.permission.OPENXR_SYSTEM'"),
            "permission org.khronos.openxr.permission.OPENXR_SYSTEM".into(),
        ),
        (
            lines
                .iter()
                .any(|l| l.starts_with("application: label='vr-ocean' icon='res/mipmap")),
            "application label vr-ocean with a mipmap icon".into(),
        ),
    ] {
        if !ok {
            problems.push(format!("no {what}"));
        }
    }
    problems
}

/// One element of `aapt dump xmltree` output.
#[derive(Debug, Default)]
pub struct XmlElement {
    /// Tag name.
    pub name: String,
    /// (attribute name without namespace prefix or resource id, value as printed: strings
    /// unquoted, others like `(type 0x12)0x0`).
    pub attrs: Vec<(String, String)>,
    /// Child elements.
    pub children: Vec<XmlElement>,
}

impl XmlElement {
    /// An attribute's value.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// Children named `name`.
    pub fn kids<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a XmlElement> + 'a {
        self.children.iter().filter(move |c| c.name == name)
    }

    /// The first child `name` whose `android:name` is `value`.
    pub fn named(&self, name: &str, value: &str) -> Option<&XmlElement> {
        self.children
            .iter()
            .find(|c| c.name == name && c.attr("name") == Some(value))
    }
}

/// Parses `aapt dump xmltree` output into its root element.
pub fn parse_xmltree(text: &str) -> Option<XmlElement> {
    // Stack of (indent, element) for open elements.
    let mut stack: Vec<(usize, XmlElement)> = Vec::new();
    let close_to = |stack: &mut Vec<(usize, XmlElement)>, indent: usize| {
        while stack.len() > 1 && stack.last().is_some_and(|(i, _)| *i >= indent) {
            let (_, done) = stack.pop().expect("non-empty");
            stack.last_mut().expect("parent").1.children.push(done);
        }
    };
    for line in text.lines() {
        let indent = line.len() - line.trim_start().len();
        let body = line.trim_start();
        if let Some(rest) = body.strip_prefix("E: ") {
            let name = rest.split_whitespace().next()?.to_string();
            close_to(&mut stack, indent);
            if stack.len() == 1 && stack[0].0 >= indent {
                return None; // a second root
            }
            stack.push((
                indent,
                XmlElement {
                    name,
                    ..XmlElement::default()
                },
            ));
        } else if let Some(rest) = body.strip_prefix("A: ") {
            close_to(&mut stack, indent);
            let (key, value) = rest.split_once('=')?;
            let key = key.split('(').next()?.trim();
            let key = key.rsplit(':').next()?.to_string();
            let value = match value.strip_prefix('"') {
                Some(v) => v.split('"').next()?.to_string(),
                None => value.trim().to_string(),
            };
            stack.last_mut()?.1.attrs.push((key, value));
        }
    }
    close_to(&mut stack, 0);
    stack.pop().map(|(_, e)| e)
}

const TRUE: &str = "(type 0x12)0xffffffff";
const FALSE: &str = "(type 0x12)0x0";

/// The compiled manifest has everything Quest and the OpenXR loader need.
pub fn check_manifest(text: &str) -> Vec<String> {
    let Some(m) = parse_xmltree(text) else {
        return vec!["cannot parse the xmltree output".into()];
    };
    let mut p = Vec::new();
    let mut need = |ok: bool, what: &str| {
        if !ok {
            p.push(what.to_string());
        }
    };
    need(m.name == "manifest", "root element is <manifest>");
    need(m.attr("package") == Some(PACKAGE), "package attribute");
    let sdk = m.kids("uses-sdk").next();
    need(
        sdk.and_then(|s| s.attr("minSdkVersion")) == Some("(type 0x10)0x1d"),
        "uses-sdk minSdkVersion 29",
    );
    need(
        sdk.and_then(|s| s.attr("targetSdkVersion")) == Some("(type 0x10)0x22"),
        "uses-sdk targetSdkVersion 34",
    );
    need(
        m.named("uses-feature", "android.hardware.vr.headtracking")
            .and_then(|f| f.attr("required"))
            == Some(TRUE),
        "uses-feature android.hardware.vr.headtracking required",
    );
    need(
        m.named("uses-feature", "android.hardware.vulkan.level")
            .is_some(),
        "uses-feature android.hardware.vulkan.level",
    );
    for perm in [
        "org.khronos.openxr.permission.OPENXR",
        "org.khronos.openxr.permission.OPENXR_SYSTEM",
    ] {
        need(
            m.named("uses-permission", perm).is_some(),
            &format!("uses-permission {perm}"),
        );
    }
    let queries = m.kids("queries").next();
    need(
        queries
            .and_then(|q| q.kids("provider").next())
            .and_then(|pr| pr.attr("authorities"))
            .is_some_and(|a| {
                let list: Vec<&str> = a.split(';').collect();
                list.contains(&"org.khronos.openxr.runtime_broker")
                    && list.contains(&"org.khronos.openxr.system_runtime_broker")
            }),
        "<queries> provider for both OpenXR runtime brokers",
    );
    need(
        queries.is_some_and(|q| {
            q.kids("intent").any(|i| {
                i.named("action", "org.khronos.openxr.OpenXRRuntimeService")
                    .is_some()
            })
        }),
        "<queries> intent org.khronos.openxr.OpenXRRuntimeService",
    );
    let Some(app) = m.kids("application").next() else {
        p.push("<application>".into());
        return p;
    };
    need(
        app.attr("hasCode") == Some(FALSE),
        "application hasCode=false",
    );
    need(
        app.attr("extractNativeLibs") == Some(FALSE),
        "application extractNativeLibs=false",
    );
    need(
        app.attr("icon").is_some_and(|i| i.starts_with('@')),
        "application icon",
    );
    need(
        app.named("meta-data", "com.oculus.supportedDevices")
            .and_then(|d| d.attr("value"))
            == Some(SUPPORTED_DEVICES),
        "meta-data com.oculus.supportedDevices = quest2|questpro|quest3|quest3s",
    );
    need(
        app.named("uses-native-library", "libopenxr_forwardloader.oculus.so")
            .and_then(|l| l.attr("required"))
            == Some(FALSE),
        "uses-native-library libopenxr_forwardloader.oculus.so required=false",
    );
    let Some(act) = app.named("activity", ACTIVITY) else {
        p.push(format!("activity {ACTIVITY}"));
        return p;
    };
    need(
        act.named("meta-data", "android.app.lib_name")
            .and_then(|d| d.attr("value"))
            == Some("vr_ocean"),
        "activity meta-data android.app.lib_name = vr_ocean",
    );
    need(act.attr("exported") == Some(TRUE), "activity exported");
    need(
        act.attr("launchMode") == Some("(type 0x10)0x2"),
        "activity launchMode singleTask",
    );
    need(
        act.attr("screenOrientation") == Some("(type 0x10)0x0"),
        "activity screenOrientation landscape",
    );
    need(
        act.attr("resizeableActivity") == Some(FALSE),
        "activity resizeableActivity=false",
    );
    let filter = act
        .kids("intent-filter")
        .find(|f| f.named("action", "android.intent.action.MAIN").is_some());
    need(filter.is_some(), "activity intent-filter with action MAIN");
    for cat in CATEGORIES {
        need(
            filter.is_some_and(|f| f.named("category", cat).is_some()),
            &format!("intent category {cat}"),
        );
    }
    p
}

/// `llvm-readelf --file-header --dynamic-table --dyn-syms --wide` of `libvr_ocean.so`.
pub fn check_elf(text: &str) -> Vec<String> {
    let mut p = Vec::new();
    let field = |name: &str| {
        text.lines()
            .find_map(|l| l.trim().strip_prefix(name).map(|v| v.trim().to_string()))
    };
    if field("Machine:").as_deref() != Some("AArch64") {
        p.push(format!("machine is {:?}, not AArch64", field("Machine:")));
    }
    if !field("Type:").is_some_and(|t| t.starts_with("DYN")) {
        p.push(format!("type is {:?}, not a shared object", field("Type:")));
    }
    let bracketed = |l: &str| {
        l.split_once('[')
            .and_then(|(_, r)| r.split_once(']'))
            .map(|(v, _)| v.to_string())
    };
    let needed: Vec<String> = text
        .lines()
        .filter(|l| l.contains("(NEEDED)"))
        .filter_map(bracketed)
        .collect();
    if needed.is_empty() {
        p.push("no NEEDED entries (is this the dynamic table?)".into());
    }
    for n in &needed {
        if !ALLOWED_NEEDED.contains(&n.as_str()) {
            p.push(format!("NEEDED {n} is not a system library"));
        }
    }
    let soname = text
        .lines()
        .find(|l| l.contains("(SONAME)"))
        .and_then(bracketed);
    if soname.as_deref() != Some("libvr_ocean.so") {
        p.push(format!(
            "SONAME is {soname:?}, not libvr_ocean.so (Android 6+ requires it)"
        ));
    }
    if text
        .lines()
        .any(|l| l.contains("(TEXTREL)") || (l.contains("(FLAGS)") && l.contains("TEXTREL")))
    {
        p.push("text relocations (TEXTREL): Android refuses to load them".into());
    }
    let exported = text.lines().any(|l| {
        let cols: Vec<&str> = l.split_whitespace().collect();
        cols.len() >= 8
            && cols[cols.len() - 1] == "ANativeActivity_onCreate"
            && cols[3] == "FUNC"
            && cols[4] == "GLOBAL"
            && cols[6] != "UND"
    });
    if !exported {
        p.push("ANativeActivity_onCreate is not exported (defined GLOBAL FUNC)".into());
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    const BADGING: &str = "\
package: name='com.vrocean.ocean' versionCode='1' versionName='0.1.0' platformBuildVersionName='10.0.0'
sdkVersion:'29'
targetSdkVersion:'34'
uses-permission: name='org.khronos.openxr.permission.OPENXR'
uses-permission: name='org.khronos.openxr.permission.OPENXR_SYSTEM'
application-label:'vr-ocean'
application: label='vr-ocean' icon='res/mipmap-mdpi-v4/ic_launcher.png'
launchable-activity: name='android.app.NativeActivity'  label='vr-ocean' icon=''
feature-group: label=''
  uses-feature: name='android.hardware.vr.headtracking' version='1'
  uses-feature: name='android.hardware.vulkan.level' version='0'
main
native-code: 'arm64-v8a'
";

    #[test]
    fn badging_passes_and_fails() {
        assert_eq!(check_badging(BADGING), Vec::<String>::new());
        for (from, to) in [
            (
                "native-code: 'arm64-v8a'",
                "native-code: 'arm64-v8a' 'armeabi-v7a'",
            ),
            ("sdkVersion:'29'", "sdkVersion:'26'"),
            ("targetSdkVersion:'34'", "targetSdkVersion:'32'"),
            (
                "launchable-activity: name='android.app.NativeActivity'",
                "activity: name='x'",
            ),
            (
                "  uses-feature: name='android.hardware.vr.headtracking'",
                "  uses-feature-not-required: name='android.hardware.vr.headtracking'",
            ),
            (
                "uses-permission: name='org.khronos.openxr.permission.OPENXR'\n",
                "",
            ),
        ] {
            let bad = BADGING.replacen(from, to, 1);
            assert_ne!(bad, BADGING);
            assert_eq!(check_badging(&bad).len(), 1, "{from} -> {to}");
        }
    }

    #[test]
    fn apksigner_output() {
        let good = "Verifies\nVerified using v1 scheme (JAR signing): false\n\
                    Verified using v2 scheme (APK Signature Scheme v2): false\n\
                    Verified using v3 scheme (APK Signature Scheme v3): true\n\
                    Number of signers: 1\n";
        assert_eq!(check_apksigner(good), Vec::<String>::new());
        let v2 = good
            .replace("v2): false", "v2): true")
            .replace("v3): true", "v3): false");
        assert_eq!(check_apksigner(&v2), Vec::<String>::new());
        assert_eq!(
            check_apksigner(&good.replace("v3): true", "v3): false")).len(),
            1
        );
        assert_eq!(
            check_apksigner(&good.replace("Verifies\n", "DOES NOT VERIFY\n")).len(),
            1
        );
        assert_eq!(
            check_apksigner(&good.replace("signers: 1", "signers: 2")).len(),
            1
        );
    }

    const TREE: &str = r#"N: android=http://schemas.android.com/apk/res/android
  E: manifest (line=5)
    A: android:versionCode(0x0101021b)=(type 0x10)0x1
    A: package="com.vrocean.ocean" (Raw: "com.vrocean.ocean")
    E: uses-sdk (line=11)
      A: android:minSdkVersion(0x0101020c)=(type 0x10)0x1d
      A: android:targetSdkVersion(0x01010270)=(type 0x10)0x22
    E: uses-feature (line=14)
      A: android:name(0x01010003)="android.hardware.vr.headtracking" (Raw: "android.hardware.vr.headtracking")
      A: android:required(0x0101028e)=(type 0x12)0xffffffff
    E: uses-feature (line=15)
      A: android:name(0x01010003)="android.hardware.vulkan.level" (Raw: "android.hardware.vulkan.level")
    E: uses-permission (line=18)
      A: android:name(0x01010003)="org.khronos.openxr.permission.OPENXR" (Raw: "org.khronos.openxr.permission.OPENXR")
    E: uses-permission (line=19)
      A: android:name(0x01010003)="org.khronos.openxr.permission.OPENXR_SYSTEM" (Raw: "org.khronos.openxr.permission.OPENXR_SYSTEM")
    E: queries (line=20)
      E: provider (line=21)
        A: android:authorities(0x01010018)="org.khronos.openxr.runtime_broker;org.khronos.openxr.system_runtime_broker" (Raw: "x")
      E: intent (line=22)
        E: action (line=23)
          A: android:name(0x01010003)="org.khronos.openxr.OpenXRRuntimeService" (Raw: "x")
    E: application (line=27)
      A: android:icon(0x01010002)=@0x7f010000
      A: android:hasCode(0x0101000c)=(type 0x12)0x0
      A: android:extractNativeLibs(0x010104ea)=(type 0x12)0x0
      E: meta-data (line=33)
        A: android:name(0x01010003)="com.oculus.supportedDevices" (Raw: "x")
        A: android:value(0x01010024)="quest2|questpro|quest3|quest3s" (Raw: "x")
      E: uses-native-library (line=37)
        A: android:name(0x01010003)="libopenxr_forwardloader.oculus.so" (Raw: "x")
        A: android:required(0x0101028e)=(type 0x12)0x0
      E: activity (line=39)
        A: android:name(0x01010003)="android.app.NativeActivity" (Raw: "android.app.NativeActivity")
        A: android:exported(0x01010010)=(type 0x12)0xffffffff
        A: android:launchMode(0x0101001d)=(type 0x10)0x2
        A: android:screenOrientation(0x0101001e)=(type 0x10)0x0
        A: android:resizeableActivity(0x010104f6)=(type 0x12)0x0
        E: meta-data (line=50)
          A: android:name(0x01010003)="android.app.lib_name" (Raw: "android.app.lib_name")
          A: android:value(0x01010024)="vr_ocean" (Raw: "vr_ocean")
        E: intent-filter (line=52)
          E: action (line=53)
            A: android:name(0x01010003)="android.intent.action.MAIN" (Raw: "x")
          E: category (line=54)
            A: android:name(0x01010003)="android.intent.category.LAUNCHER" (Raw: "x")
          E: category (line=55)
            A: android:name(0x01010003)="com.oculus.intent.category.VR" (Raw: "x")
          E: category (line=56)
            A: android:name(0x01010003)="org.khronos.openxr.intent.category.IMMERSIVE_HMD" (Raw: "x")
"#;

    #[test]
    fn manifest_tree_passes_and_each_mistake_fails() {
        assert_eq!(check_manifest(TREE), Vec::<String>::new());
        for (from, to) in [
            (
                "com.oculus.intent.category.VR",
                "com.oculus.intent.category.XR",
            ),
            ("IMMERSIVE_HMD", "IMMERSIVE"),
            ("\"vr_ocean\"", "\"vr-ocean\""),
            ("quest2|questpro|quest3|quest3s", "quest2|quest3"),
            (
                "hasCode(0x0101000c)=(type 0x12)0x0",
                "hasCode(0x0101000c)=(type 0x12)0xffffffff",
            ),
            (
                "launchMode(0x0101001d)=(type 0x10)0x2",
                "launchMode(0x0101001d)=(type 0x10)0x0",
            ),
            (
                "minSdkVersion(0x0101020c)=(type 0x10)0x1d",
                "minSdkVersion(0x0101020c)=(type 0x10)0x1a",
            ),
            (";org.khronos.openxr.system_runtime_broker", ""),
            ("OpenXRRuntimeService", "RuntimeService"),
            (
                "libopenxr_forwardloader.oculus.so",
                "libopenxr_forwardloader.so",
            ),
            (
                "resizeableActivity(0x010104f6)=(type 0x12)0x0",
                "resizeableActivity(0x010104f6)=(type 0x12)0xffffffff",
            ),
        ] {
            let bad = TREE.replacen(from, to, 1);
            assert_ne!(bad, TREE);
            assert_eq!(
                check_manifest(&bad).len(),
                1,
                "{from} -> {to}: {:?}",
                check_manifest(&bad)
            );
        }
        // A category moved out of the intent filter (same text, wrong place) fails too.
        let moved = TREE.replace(
            "          E: category (line=55)\n            A: android:name(0x01010003)=\"com.oculus.intent.category.VR\" (Raw: \"x\")\n",
            "",
        ) + "      E: category (line=90)\n        A: android:name(0x01010003)=\"com.oculus.intent.category.VR\" (Raw: \"x\")\n";
        assert_eq!(check_manifest(&moved).len(), 1);
        assert!(!check_manifest("garbage").is_empty());
    }

    const ELF: &str = "\
ELF Header:
  Class:                             ELF64
  Type:                              DYN (Shared object file)
  Machine:                           AArch64
Dynamic section at offset 0x1 contains 30 entries:
  Tag                Type                 Name/Value
  0x0000000000000001 (NEEDED)             Shared library: [liblog.so]
  0x0000000000000001 (NEEDED)             Shared library: [libc.so]
  0x0000000000000001 (NEEDED)             Shared library: [libdl.so]
  0x000000000000000e (SONAME)             Library soname: [libvr_ocean.so]
  0x000000006ffffffb (FLAGS_1)            Flags: NOW
Symbol table '.dynsym' contains 3 entries:
   Num:    Value          Size Type    Bind   Vis       Ndx Name
     1: 0000000000000000     0 FUNC    GLOBAL DEFAULT   UND malloc@LIBC
     2: 00000000001a2b3c   120 FUNC    GLOBAL DEFAULT    12 ANativeActivity_onCreate
";

    #[test]
    fn elf_passes_and_each_mistake_fails() {
        assert_eq!(check_elf(ELF), Vec::<String>::new());
        for (from, to) in [
            ("[liblog.so]", "[libvulkan.so]"),
            ("[libdl.so]", "[libc++_shared.so]"),
            ("AArch64", "X86-64"),
            ("DYN (Shared", "EXEC (Executable"),
            ("[libvr_ocean.so]", "[libfoo.so]"),
            (
                "(FLAGS_1)            Flags: NOW",
                "(FLAGS)              Flags: TEXTREL",
            ),
            (
                "DEFAULT    12 ANativeActivity_onCreate",
                "DEFAULT   UND ANativeActivity_onCreate",
            ),
            (
                "FUNC    GLOBAL DEFAULT    12",
                "FUNC    LOCAL  DEFAULT    12",
            ),
        ] {
            let bad = ELF.replacen(from, to, 1);
            assert_ne!(bad, ELF);
            assert_eq!(
                check_elf(&bad).len(),
                1,
                "{from} -> {to}: {:?}",
                check_elf(&bad)
            );
        }
    }

    const LISTING: &str = "\
Archive:  x.apk
 Length   Method    Size  Ratio   Offset      Date  Time  CRC-32    Name
--------  ------  ------- -----  -------      ----  ----  ------    ----
    4856  Deflate    1522  69%         0  01-01-80 00:00  9f04d807  AndroidManifest.xml
    1352  Stored     1352   0%     28654  01-01-80 00:00  588f5cf3  resources.arsc
 9999999  Stored  9999999   0%     32768  01-01-80 00:00  12345678  lib/arm64-v8a/libvr_ocean.so
    5000  Stored     5000   0%   9999999  01-01-80 00:00  12345678  lib/arm64-v8a/libopenxr_loader.so
";

    #[test]
    fn listing_passes_and_fails() {
        assert_eq!(check_listing(LISTING, true), Vec::<String>::new());
        assert_eq!(check_listing(LISTING, false).len(), 1, "unexpected loader");
        let no_loader = LISTING.replace("lib/arm64-v8a/libopenxr_loader.so", "assets/x");
        assert_eq!(check_listing(&no_loader, false), Vec::<String>::new());
        assert_eq!(check_listing(&no_loader, true).len(), 1);
        let deflated = LISTING.replacen("Stored  9999999", "Deflate 9999999", 1);
        assert_eq!(check_listing(&deflated, true).len(), 1);
        let other_abi = LISTING.replace("lib/arm64-v8a/libopenxr", "lib/armeabi-v7a/libopenxr");
        assert_eq!(check_listing(&other_abi, true).len(), 2);
    }
}
