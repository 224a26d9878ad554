//! Reading an apitrace GL trace (`apitrace dump` text) for a bug report: the GLSL wgpu-hal gave
//! the driver, labelled with the WGSL file naga translated it from, and, for every texture the
//! case read back (`glReadPixels`), the call after which that texture is the draw framebuffer's
//! first draw buffer — where `eglretrace -S CALL -s DIR/` writes its pixels. The read-back
//! itself goes into a pixel-pack buffer that a replay never shows.

use std::collections::HashMap;

/// One shader as the trace gave it to the driver.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TracedShader {
    pub call: u64,
    /// `vert`, `frag` (or the GL type's name).
    pub stage: String,
    /// The object label wgpu-hal set: the WGSL file under `shaders/` it came from.
    pub label: Option<String>,
    pub source: String,
}

/// One `glReadPixels` of a texture, and where a replay can show that texture.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TracedReadback {
    /// The `glReadPixels` call.
    pub call: u64,
    pub size: (u32, u32),
    /// The call after which the texture is the draw framebuffer's first draw buffer (a snapshot
    /// there holds the pixels read), or why there is none.
    pub snapshot: Result<u64, String>,
}

/// What a bug report needs from a trace.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TraceReading {
    pub shaders: Vec<TracedShader>,
    pub readbacks: Vec<TracedReadback>,
}

/// What an attachment point holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Attached {
    Texture { texture: u64, level: u64, layer: u64 },
    Renderbuffer(u64),
}

/// The framebuffer state the parser follows.
#[derive(Default)]
struct FramebufferState {
    draw: u64,
    read: u64,
    /// (framebuffer, attachment point) → what it holds.
    attachments: HashMap<(u64, String), Attached>,
    /// Per framebuffer: its first draw buffer and its read buffer (default: colour attachment 0).
    draw_buffer: HashMap<u64, String>,
    read_buffer: HashMap<u64, String>,
    /// Per attachment: the last call that wrote it, and whether it was then the first draw buffer.
    last_write: HashMap<Attached, (u64, bool)>,
}

const COLOR0: &str = "GL_COLOR_ATTACHMENT0";

impl FramebufferState {
    fn bound(&self, target: &str) -> u64 {
        if target == "GL_READ_FRAMEBUFFER" { self.read } else { self.draw }
    }

    fn first_draw_buffer(&self, framebuffer: u64) -> String {
        self.draw_buffer.get(&framebuffer).cloned().unwrap_or_else(|| COLOR0.to_owned())
    }

    /// A call that writes the draw framebuffer's attachments.
    fn written(&mut self, call: u64) {
        let first = self.first_draw_buffer(self.draw);
        let written: Vec<(Attached, bool)> = self
            .attachments
            .iter()
            .filter(|((framebuffer, _), _)| *framebuffer == self.draw)
            .map(|((_, point), attached)| (*attached, *point == first))
            .collect();
        for (attached, shown) in written {
            self.last_write.insert(attached, (call, shown));
        }
    }
}

/// One call of the dump: its number, function, arguments (name → value text) and result.
struct Call<'a> {
    number: u64,
    function: &'a str,
    arguments: Vec<(&'a str, &'a str)>,
    result: Option<&'a str>,
}

impl Call<'_> {
    fn argument(&self, name: &str) -> Option<&str> {
        self.arguments.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
    }

    fn number_argument(&self, name: &str) -> Option<u64> {
        self.argument(name)?.trim_start_matches('&').parse().ok()
    }
}

/// Splits `a = 1, b = {x, y}, c = &"s, t"` at its top-level commas into (name, value) pairs.
fn split_arguments(text: &str) -> Vec<(&str, &str)> {
    let mut pairs = Vec::new();
    let (mut depth, mut quoted, mut escaped, mut start) = (0i32, false, false, 0);
    let bytes = text.as_bytes();
    for (i, &b) in bytes.iter().enumerate() {
        if quoted {
            match (escaped, b) {
                (true, _) => escaped = false,
                (false, b'\\') => escaped = true,
                (false, b'"') => quoted = false,
                _ => {}
            }
            continue;
        }
        match b {
            b'"' => quoted = true,
            b'{' | b'(' | b'[' => depth += 1,
            b'}' | b')' | b']' => depth -= 1,
            b',' if depth == 0 => {
                pairs.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    pairs.push(&text[start..]);
    pairs
        .into_iter()
        .filter_map(|pair| {
            let (name, value) = pair.split_once(" = ")?;
            Some((name.trim(), value.trim()))
        })
        .collect()
}

/// Whether a dump line starts a call: `NUMBER function(` (GL, EGL or GLX).
fn starts_a_call(line: &str) -> bool {
    let Some((number, rest)) = line.split_once(' ') else {
        return false;
    };
    let name_length = rest.bytes().take_while(|b| b.is_ascii_alphanumeric() || *b == b'_').count();
    !number.is_empty()
        && number.bytes().all(|b| b.is_ascii_digit())
        && name_length > 0
        && rest.as_bytes().get(name_length) == Some(&b'(')
}

/// The calls of `apitrace dump --color=never` text: each starts a line with its number; a
/// string argument may run over several lines.
fn calls(dump: &str) -> Vec<Call<'_>> {
    let mut starts: Vec<usize> = Vec::new();
    let mut offset = 0;
    for line in dump.split_inclusive('\n') {
        if starts_a_call(line) {
            starts.push(offset);
        }
        offset += line.len();
    }
    starts.push(dump.len());
    starts
        .windows(2)
        .filter_map(|pair| {
            let text = dump[pair[0]..pair[1]].trim_end();
            let (number, rest) = text.split_once(' ')?;
            let open = rest.find('(')?;
            let close = rest.rfind(')')?;
            Some(Call {
                number: number.parse().ok()?,
                function: &rest[..open],
                arguments: split_arguments(&rest[open + 1..close]),
                result: rest[close + 1..].trim().strip_prefix("= "),
            })
        })
        .collect()
}

/// A dumped string argument (`&"text"`), unescaped.
fn string_value(value: &str) -> Option<String> {
    let inner = value.trim_start_matches('&').strip_prefix('"')?.strip_suffix('"')?;
    let mut text = String::with_capacity(inner.len());
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c == '\\' {
            match chars.next() {
                Some('n') => text.push('\n'),
                Some('t') => text.push('\t'),
                Some(other) => text.push(other),
                None => {}
            }
        } else {
            text.push(c);
        }
    }
    Some(text)
}

fn stage_name(gl_type: &str) -> String {
    match gl_type {
        "GL_VERTEX_SHADER" => "vert".to_owned(),
        "GL_FRAGMENT_SHADER" => "frag".to_owned(),
        other => other.trim_start_matches("GL_").to_ascii_lowercase(),
    }
}

/// Reads `dump` (`apitrace dump --color=never TRACE`).
pub fn read_trace(dump: &str) -> TraceReading {
    let mut reading = TraceReading::default();
    let mut state = FramebufferState::default();
    let mut shader_types: HashMap<u64, String> = HashMap::new();
    let mut labels: HashMap<u64, String> = HashMap::new();
    for call in calls(dump) {
        match call.function {
            "glCreateShader" => {
                if let (Some(id), Some(kind)) = (call.result.and_then(|r| r.parse().ok()), call.argument("type")) {
                    shader_types.insert(id, stage_name(kind));
                }
            }
            "glObjectLabel" if call.argument("identifier") == Some("GL_SHADER") => {
                if let (Some(id), Some(label)) = (call.number_argument("name"), call.argument("label")) {
                    labels.insert(id, string_value(label).unwrap_or_else(|| label.to_owned()));
                }
            }
            "glShaderSource" => {
                if let (Some(id), Some(source)) =
                    (call.number_argument("shader"), call.argument("string").and_then(string_value))
                {
                    reading.shaders.push(TracedShader {
                        call: call.number,
                        stage: shader_types.get(&id).cloned().unwrap_or_else(|| "shader".to_owned()),
                        label: labels.get(&id).cloned(),
                        source,
                    });
                }
            }
            "glBindFramebuffer" => {
                let framebuffer = call.number_argument("framebuffer").unwrap_or(0);
                match call.argument("target") {
                    Some("GL_READ_FRAMEBUFFER") => state.read = framebuffer,
                    Some("GL_DRAW_FRAMEBUFFER") => state.draw = framebuffer,
                    _ => (state.read, state.draw) = (framebuffer, framebuffer),
                }
            }
            "glFramebufferTexture2D" | "glFramebufferTexture" | "glFramebufferTextureLayer" => {
                let framebuffer = state.bound(call.argument("target").unwrap_or_default());
                let point = call.argument("attachment").unwrap_or_default().to_owned();
                match call.number_argument("texture") {
                    Some(0) | None => state.attachments.remove(&(framebuffer, point)),
                    Some(texture) => {
                        let level = call.number_argument("level").unwrap_or(0);
                        let layer = call.number_argument("layer").unwrap_or(0);
                        state.attachments.insert((framebuffer, point), Attached::Texture { texture, level, layer })
                    }
                };
            }
            "glFramebufferRenderbuffer" => {
                let framebuffer = state.bound(call.argument("target").unwrap_or_default());
                let point = call.argument("attachment").unwrap_or_default().to_owned();
                match call.number_argument("renderbuffer") {
                    Some(0) | None => state.attachments.remove(&(framebuffer, point)),
                    Some(renderbuffer) => {
                        state.attachments.insert((framebuffer, point), Attached::Renderbuffer(renderbuffer))
                    }
                };
            }
            "glDrawBuffers" | "glDrawBuffer" => {
                let value = call.argument("bufs").or_else(|| call.argument("buf")).unwrap_or_default();
                let first = value.trim_start_matches('&').trim_start_matches('{').split(',').next().unwrap_or_default();
                state.draw_buffer.insert(state.draw, first.trim().trim_end_matches('}').to_owned());
            }
            "glReadBuffer" => {
                state.read_buffer.insert(state.read, call.argument("mode").unwrap_or(COLOR0).to_owned());
            }
            function
                if function.starts_with("glDraw") && !function.starts_with("glDrawBuffer")
                    || function.starts_with("glClear") && function != "glClearColor" && function != "glClearDepth"
                    || function == "glBlitFramebuffer" =>
            {
                state.written(call.number);
            }
            "glReadPixels" => {
                let point = state.read_buffer.get(&state.read).cloned().unwrap_or_else(|| COLOR0.to_owned());
                let size = (
                    call.number_argument("width").unwrap_or(0) as u32,
                    call.number_argument("height").unwrap_or(0) as u32,
                );
                let snapshot = match state.attachments.get(&(state.read, point.clone())) {
                    None => Err(format!("the read framebuffer {} has nothing at {point}", state.read)),
                    Some(attached) => match state.last_write.get(attached) {
                        None => Err(format!("nothing drew into {attached:?} before it was read")),
                        Some((_, false)) => Err(format!(
                            "{attached:?} was last written as another draw buffer than the first, which snapshots show"
                        )),
                        Some((call, true)) => Ok(*call),
                    },
                };
                reading.readbacks.push(TracedReadback { call: call.number, size, snapshot });
            }
            _ => {}
        }
    }
    reading
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lines of a trace of `kit.msaa.sample_mask` on llvmpipe GL (apitrace 11.1): a 4x draw
    /// into a renderbuffer, resolved by a blit into texture 1, read back from framebuffer 2.
    const DUMP: &str = r##"3123 glCreateShader(type = GL_VERTEX_SHADER) = 2
3124 glObjectLabel(identifier = GL_SHADER, name = 2, length = 13, label = "kit/rect.wgsl")
3125 glShaderSource(shader = 2, count = 1, string = &"#version 450 core
void main() {
    gl_Position = vec4(0.0, \"q\", 0.0, 1.0);
}

", length = &1097)
3250 glFlush()
3251 eglMakeCurrent(dpy = 0x56348945e0f0, draw = NULL, read = NULL, ctx = NULL) = EGL_TRUE
3252 glFramebufferTexture2D(target = GL_DRAW_FRAMEBUFFER, attachment = GL_COLOR_ATTACHMENT0, textarget = GL_TEXTURE_2D, texture = 0, level = 0)
3270 glBindFramebuffer(target = GL_DRAW_FRAMEBUFFER, framebuffer = 1)
3271 glFramebufferRenderbuffer(target = GL_DRAW_FRAMEBUFFER, attachment = GL_COLOR_ATTACHMENT0, renderbuffertarget = GL_RENDERBUFFER, renderbuffer = 1)
3272 glDrawBuffers(n = 1, bufs = &GL_COLOR_ATTACHMENT0)
3273 glClearBufferfv(buffer = GL_COLOR, drawbuffer = 0, value = {0, 0, 0, 0})
3291 glDrawArraysInstancedBaseInstance(mode = GL_TRIANGLES, first = 0, count = 6, instancecount = 1, baseinstance = 0)
3292 glBindFramebuffer(target = GL_READ_FRAMEBUFFER, framebuffer = 1)
3293 glReadBuffer(mode = GL_COLOR_ATTACHMENT0)
3294 glBindFramebuffer(target = GL_DRAW_FRAMEBUFFER, framebuffer = 2)
3295 glFramebufferTexture2D(target = GL_DRAW_FRAMEBUFFER, attachment = GL_COLOR_ATTACHMENT0, textarget = GL_TEXTURE_2D, texture = 1, level = 0)
3296 glBlitFramebuffer(srcX0 = 0, srcY0 = 0, srcX1 = 8, srcY1 = 8, dstX0 = 0, dstY0 = 0, dstX1 = 8, dstY1 = 8, mask = GL_COLOR_BUFFER_BIT, filter = GL_NEAREST)
3297 glBindFramebuffer(target = GL_READ_FRAMEBUFFER, framebuffer = 0)
3298 glBindFramebuffer(target = GL_DRAW_FRAMEBUFFER, framebuffer = 1)
3302 glBindFramebuffer(target = GL_FRAMEBUFFER, framebuffer = 0)
3363 glBindFramebuffer(target = GL_READ_FRAMEBUFFER, framebuffer = 2)
3364 glFramebufferTexture2D(target = GL_READ_FRAMEBUFFER, attachment = GL_COLOR_ATTACHMENT0, textarget = GL_TEXTURE_2D, texture = 1, level = 0)
3365 glPixelStorei(pname = GL_PACK_ROW_LENGTH, param = 64)
3367 glReadPixels(x = 0, y = 0, width = 8, height = 8, format = GL_RGBA, type = GL_UNSIGNED_BYTE, pixels = NULL)
3400 glBindFramebuffer(target = GL_READ_FRAMEBUFFER, framebuffer = 3)
3401 glFramebufferTexture2D(target = GL_READ_FRAMEBUFFER, attachment = GL_COLOR_ATTACHMENT0, textarget = GL_TEXTURE_2D, texture = 9, level = 0)
3402 glReadPixels(x = 0, y = 0, width = 4, height = 2, format = GL_RGBA, type = GL_UNSIGNED_BYTE, pixels = NULL)
"##;

    #[test]
    fn a_read_back_texture_is_shown_after_the_call_that_last_drew_it() {
        let reading = read_trace(DUMP);
        assert_eq!(reading.readbacks.len(), 2);
        assert_eq!(reading.readbacks[0], TracedReadback { call: 3367, size: (8, 8), snapshot: Ok(3296) });
        // A texture nothing drew into (an upload, say) has no snapshot, and says so.
        let untraced = &reading.readbacks[1];
        assert_eq!((untraced.call, untraced.size), (3402, (4, 2)));
        assert!(untraced.snapshot.as_ref().unwrap_err().contains("nothing drew into"), "{untraced:?}");
    }

    #[test]
    fn shaders_keep_their_stage_their_wgsl_label_and_their_text() {
        let reading = read_trace(DUMP);
        assert_eq!(reading.shaders.len(), 1);
        let shader = &reading.shaders[0];
        assert_eq!(
            (shader.call, shader.stage.as_str(), shader.label.as_deref()),
            (3125, "vert", Some("kit/rect.wgsl"))
        );
        assert_eq!(
            shader.source,
            "#version 450 core\nvoid main() {\n    gl_Position = vec4(0.0, \"q\", 0.0, 1.0);\n}\n\n"
        );
    }

    #[test]
    fn arguments_split_at_top_level_commas_only() {
        let pairs = split_arguments(r#"a = 1, b = {2, 3}, c = &"x, \"y\"", d = f(4, 5)"#);
        assert_eq!(pairs, [("a", "1"), ("b", "{2, 3}"), ("c", r#"&"x, \"y\"""#), ("d", "f(4, 5)")]);
    }

    #[test]
    fn a_texture_last_written_as_a_second_draw_buffer_is_not_snapshotted() {
        let dump = "1 glBindFramebuffer(target = GL_FRAMEBUFFER, framebuffer = 4)
2 glFramebufferTexture2D(target = GL_FRAMEBUFFER, attachment = GL_COLOR_ATTACHMENT1, textarget = GL_TEXTURE_2D, texture = 7, level = 0)
3 glDrawBuffers(n = 2, bufs = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1})
4 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)
5 glReadBuffer(mode = GL_COLOR_ATTACHMENT1)
6 glReadPixels(x = 0, y = 0, width = 2, height = 2, format = GL_RGBA, type = GL_UNSIGNED_BYTE, pixels = NULL)
";
        let reading = read_trace(dump);
        assert!(reading.readbacks[0].snapshot.as_ref().unwrap_err().contains("another draw buffer"), "{reading:?}");
    }
}
