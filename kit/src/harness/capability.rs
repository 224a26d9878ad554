//! Capabilities an adapter lacks, as wgpu says when the kit tries to use them: a downlevel
//! adapter (softpipe's GL 3.3) refuses a pipeline that needs independent blending, or a shader
//! with per-sample interpolation, and naga will not write GLSL 3.30 with storage buffers. The
//! attempt is the probe; its refusal, in wgpu's words, is the `not_supported` reason — never a
//! failure of the case, and never guessed from a flag.

/// The missing capability a wgpu error names, or None when the error is anything else.
pub fn missing_capability(error: &str) -> Option<String> {
    let named = |marker: &str, end: &str| {
        let start = error.find(marker)? + marker.len();
        let length = error[start..].find(end)?;
        Some(error[start..start + length].to_owned())
    };
    if let Some(flags) = named("Downlevel flags DownlevelFlags(", ")") {
        return Some(format!("{flags} (wgpu refuses the pipeline: the adapter's API lacks it)"));
    }
    if let Some(features) = named("The selected version doesn't support Features(", ")") {
        return Some(format!("{features} (naga's GLSL for the adapter's GL version has none: the API lacks it)"));
    }
    named("Capability Capabilities(", ")")
        .map(|capability| format!("{capability} (wgpu refuses the shader: the adapter's API lacks it)"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downlevel_and_shader_capability_refusals_are_named() {
        let pipeline = "In Device::create_render_pipeline, label = 'weighted accumulate'\n    Downlevel flags DownlevelFlags(INDEPENDENT_BLEND) are required but not supported on the device.";
        assert_eq!(
            missing_capability(pipeline).as_deref(),
            Some("INDEPENDENT_BLEND (wgpu refuses the pipeline: the adapter's API lacks it)")
        );
        let shader = "Shader validation error: Entry point vs_scene at Vertex is invalid\n = Capability Capabilities(MULTISAMPLED_SHADING) is not supported";
        assert!(missing_capability(shader).unwrap().starts_with("MULTISAMPLED_SHADING"));
        // GL 3.3 (softpipe) has no shader storage buffers; naga's GLSL writer says so.
        let glsl = "Internal error in ShaderStages(FRAGMENT) shader: The selected version doesn't support Features(BUFFER_STORAGE)";
        assert!(missing_capability(glsl).unwrap().starts_with("BUFFER_STORAGE (naga's GLSL"));
        assert_eq!(missing_capability("Validation Error: Dimension X is zero"), None);
    }
}
