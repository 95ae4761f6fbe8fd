//! three.js as a classic script: the conversion `build.rs` runs on the vendored module (this
//! file is compiled into the build script too, so it uses `std` alone).

/// The module's final `export{a as B,...};` becomes `window.THREE={B:a,...};` and the whole
/// runs inside a strict-mode function, so its top-level names stay private. `None` if the
/// module is not of that form (one export statement, at the end, no import) or would end the
/// page's script element early (`</script` in any case).
pub fn to_classic(module: &str) -> Option<String> {
    let at = module.rfind("export{")?;
    let tail = module[at + "export{".len()..].trim_end();
    let list = tail.strip_suffix("};").or_else(|| tail.strip_suffix('}'))?;
    if list.contains(['{', '}', ';']) || module[..at].contains("export{") {
        return None;
    }
    let mut members = Vec::new();
    for item in list.split(',') {
        let mut words = item.split(" as ");
        let local = words.next()?.trim();
        let exported = words.next().unwrap_or(local).trim();
        let ident = |s: &str| {
            !s.is_empty()
                && s.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '$')
        };
        if !ident(local) || !ident(exported) || words.next().is_some() {
            return None;
        }
        members.push(format!("{exported}:{local}"));
    }
    let body = &module[..at];
    if ["import{", "import*", "import\"", "import \""]
        .iter()
        .any(|i| body.contains(i))
    {
        return None;
    }
    let out = format!(
        "(function(){{\"use strict\";\n{body}\nwindow.THREE={{{}}};\n}})();",
        members.join(",")
    );
    (!out.to_ascii_lowercase().contains("</script")).then_some(out)
}
