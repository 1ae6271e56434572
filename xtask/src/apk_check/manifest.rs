//! The compiled manifest (`aapt dump xmltree AndroidManifest.xml`): everything Quest and the
//! OpenXR loader need, each in its place.

use super::xmltree::parse_xmltree;
use crate::apk::{ACTIVITY, PACKAGE};

/// Intent categories the activity must have.
pub const CATEGORIES: &[&str] = &[
    "android.intent.category.LAUNCHER",
    "com.oculus.intent.category.VR",
    "org.khronos.openxr.intent.category.IMMERSIVE_HMD",
];

/// Quest devices the app declares.
pub const SUPPORTED_DEVICES: &str = "quest2|questpro|quest3|quest3s";

/// A true boolean attribute as aapt prints it.
const TRUE: &str = "(type 0x12)0xffffffff";
/// A false boolean attribute as aapt prints it.
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
