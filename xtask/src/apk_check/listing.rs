//! The APK's members (`aapt list -v`): which native libraries, and stored uncompressed.

/// The app's native library in the APK.
pub const LIB: &str = "lib/arm64-v8a/libvr_ocean.so";
/// The OpenXR loader in the APK.
pub const LOADER: &str = "lib/arm64-v8a/libopenxr_loader.so";

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

#[cfg(test)]
mod tests {
    use super::*;

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
