//! The APK's signature (`apksigner verify --verbose`).

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

#[cfg(test)]
mod tests {
    use super::*;

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
}
