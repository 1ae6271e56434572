//! The packaged `libvr_ocean.so` (`llvm-readelf`): an AArch64 shared object with its SONAME,
//! the NativeActivity entry point exported, only system libraries needed, no text relocations.

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
}
