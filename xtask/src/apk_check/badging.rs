//! `aapt dump badging`: the package, SDK levels, activity, ABI, features and permissions
//! Quest's installer and launcher read.

use crate::apk::{ACTIVITY, PACKAGE};

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
}
