//! A bug report's shaders: each WGSL file the case declares as the kit compiles it (the common
//! snippets prepended), and what the driver got: on GL the GLSL wgpu-hal passed to
//! `glShaderSource`, read from the capture; on Vulkan the SPIR-V naga writes for the module with
//! its default options, and `spirv-dis`'s text of it.

use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result};
use wgpu::naga;

use super::gl_trace::TracedShader;
use crate::shaders::ShaderFile;

/// One file written, and what it is.
pub struct WrittenShader {
    pub path: String,
    pub about: String,
}

fn write(dir: &Path, relative: &str, contents: &[u8]) -> Result<()> {
    let path = dir.join(relative);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).with_context(|| format!("creating {}", parent.display()))?;
    }
    std::fs::write(&path, contents).with_context(|| format!("writing {}", path.display()))
}

/// Writes the shaders of a case's `files` under `dir` (the report's `shaders/`); `traced` are the
/// GLSL shaders a GL capture holds.
pub fn write_shaders(
    dir: &Path,
    files: &[ShaderFile],
    backend: &str,
    traced: &[TracedShader],
) -> Result<Vec<WrittenShader>> {
    let mut written = Vec::new();
    for file in files {
        let wgsl = format!("wgsl/{}", file.path);
        write(dir, &wgsl, file.assembled().as_bytes())?;
        written.push(WrittenShader {
            path: wgsl.clone(),
            about: format!("the WGSL the kit compiles ({}), common snippets first", file.module),
        });
        if backend == "vulkan" {
            match write_spirv(dir, file) {
                Ok(spirv) => written.extend(spirv),
                Err(e) => written.push(WrittenShader { path: wgsl.clone(), about: format!("no SPIR-V of it: {e:#}") }),
            }
        }
    }
    // Each distinct shader once (a case builds the same pipeline for each of its runs).
    let mut distinct: Vec<(&TracedShader, usize)> = Vec::new();
    for shader in traced {
        let same = |seen: &&TracedShader| {
            (&seen.label, &seen.stage, &seen.source) == (&shader.label, &shader.stage, &shader.source)
        };
        match distinct.iter_mut().find(|(seen, _)| same(seen)) {
            Some((_, count)) => *count += 1,
            None => distinct.push((shader, 1)),
        }
    }
    for (index, (shader, count)) in distinct.into_iter().enumerate() {
        let stem = shader
            .label
            .as_deref()
            .map_or_else(|| "unlabelled".to_owned(), |l| l.replace('/', "_").replace(".wgsl", ""));
        let path = format!("glsl/{index:02}-{stem}.{}", shader.stage);
        write(dir, &path, shader.source.as_bytes())?;
        let again = if count > 1 { format!("; compiled {count} times") } else { String::new() };
        written.push(WrittenShader {
            path,
            about: format!(
                "the GLSL wgpu-hal gave glShaderSource (trace call {}{again}), from {}",
                shader.call,
                shader.label.as_deref().unwrap_or("an unlabelled module")
            ),
        });
    }
    Ok(written)
}

/// naga's SPIR-V of one file's module and its disassembly.
fn write_spirv(dir: &Path, file: &ShaderFile) -> Result<Vec<WrittenShader>> {
    let source = file.assembled();
    let module = naga::front::wgsl::parse_str(&source).with_context(|| format!("naga parsing {}", file.path))?;
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
        .validate(&module)
        .with_context(|| format!("naga validating {}", file.path))?;
    // Override constants at their defaults (the pipelines may set others: the specialisation of
    // each pipeline is in the capture, not here).
    let (module, info) = naga::back::pipeline_constants::process_overrides(&module, &info, None, &Default::default())
        .with_context(|| format!("naga giving {}'s override constants their defaults", file.path))?;
    let words = naga::back::spv::write_vec(&module, &info, &naga::back::spv::Options::default(), None)
        .with_context(|| format!("naga writing SPIR-V of {}", file.path))?;
    let spv = format!("spirv/{}.spv", file.path.trim_end_matches(".wgsl"));
    write(dir, &spv, &words.iter().flat_map(|w| w.to_le_bytes()).collect::<Vec<u8>>())?;
    let mut written = vec![WrittenShader {
        path: spv.clone(),
        about: "SPIR-V naga (wgpu 30's) writes for the whole module with its default options and override constants at their defaults (wgpu-hal's own options differ in bounds-check policy and debug info; each pipeline sets its constants)".to_owned(),
    }];
    let text = format!("{}.spvasm", spv.trim_end_matches(".spv"));
    let disassembled = Command::new("spirv-dis").arg(dir.join(&spv)).arg("-o").arg(dir.join(&text)).output();
    match disassembled {
        Ok(output) if output.status.success() => {
            written.push(WrittenShader { path: text, about: "spirv-dis's text of it".to_owned() })
        }
        Ok(output) => written.push(WrittenShader {
            path: spv,
            about: format!("spirv-dis could not read it: {}", String::from_utf8_lossy(&output.stderr).trim()),
        }),
        Err(_) => written.push(WrittenShader {
            path: spv,
            about: "no disassembly: spirv-dis is not on the PATH (Debian: apt-get install spirv-tools)".to_owned(),
        }),
    }
    Ok(written)
}
