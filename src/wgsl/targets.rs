//! Cross-compiling a validated module with naga's backends.

use super::{ShaderError, ShaderModule};
use std::fmt;

/// An output language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// WGSL, as generated.
    Wgsl,
    /// SPIR-V 1.0 binary.
    SpirV,
    /// GLSL 4.50 core.
    Glsl,
    /// Metal Shading Language 2.0.
    Msl,
    /// HLSL shader model 5.1.
    Hlsl,
}

impl Target {
    /// Every target.
    pub const ALL: [Target; 5] = [
        Target::Wgsl,
        Target::SpirV,
        Target::Glsl,
        Target::Msl,
        Target::Hlsl,
    ];
    /// The name used on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            Target::Wgsl => "wgsl",
            Target::SpirV => "spirv",
            Target::Glsl => "glsl",
            Target::Msl => "msl",
            Target::Hlsl => "hlsl",
        }
    }
    /// Parses a name written by [`Target::name`].
    pub fn from_name(name: &str) -> Option<Target> {
        Target::ALL.into_iter().find(|t| t.name() == name)
    }
}

impl fmt::Display for Target {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

pub(super) fn translate(m: &ShaderModule, target: Target) -> Result<Vec<u8>, ShaderError> {
    let err = |message: String| ShaderError::Backend {
        target: target.name(),
        message,
    };
    let entry = m.entry.function().to_owned();
    let stage = m.entry.stage();
    // Modules with several entry points (or none) are written whole where the backend can;
    // GLSL holds one stage, the fragment one of a render module.
    let single = matches!(m.entry, super::Entry::Compute | super::Entry::Fragment);
    if target == Target::Glsl && matches!(m.entry, super::Entry::Library(_)) {
        return Err(err(
            "GLSL needs an entry point; a library module has none".into()
        ));
    }
    match target {
        Target::Wgsl => Ok(m.source.clone().into_bytes()),
        Target::SpirV => {
            use naga::back::spv;
            // Explicit flags: the default adds debug info in debug builds only, which would make
            // the output depend on the build profile.
            let options = spv::Options {
                lang_version: (1, 0),
                flags: spv::WriterFlags::ADJUST_COORDINATE_SPACE
                    | spv::WriterFlags::LABEL_VARYINGS
                    | spv::WriterFlags::CLAMP_FRAG_DEPTH,
                ..spv::Options::default()
            };
            let pipeline = spv::PipelineOptions {
                shader_stage: stage,
                entry_point: entry,
            };
            let words = spv::write_vec(&m.module, &m.info, &options, single.then_some(&pipeline))
                .map_err(|e| err(e.to_string()))?;
            Ok(words.iter().flat_map(|w| w.to_le_bytes()).collect())
        }
        Target::Glsl => {
            use naga::back::glsl;
            let options = glsl::Options {
                version: glsl::Version::Desktop(450),
                ..glsl::Options::default()
            };
            let pipeline = glsl::PipelineOptions {
                shader_stage: stage,
                entry_point: entry,
                multiview: None,
            };
            let mut text = String::new();
            let mut w = glsl::Writer::new(
                &mut text,
                &m.module,
                &m.info,
                &options,
                &pipeline,
                naga::proc::BoundsCheckPolicies::default(),
            )
            .map_err(|e| err(e.to_string()))?;
            w.write().map_err(|e| err(e.to_string()))?;
            Ok(text.into_bytes())
        }
        Target::Msl => {
            use naga::back::msl;
            let options = msl::Options {
                lang_version: (2, 0),
                ..msl::Options::default()
            };
            let pipeline = msl::PipelineOptions {
                entry_point: single.then_some((stage, entry)),
                ..msl::PipelineOptions::default()
            };
            let (text, _) = msl::write_string(&m.module, &m.info, &options, &pipeline)
                .map_err(|e| err(e.to_string()))?;
            Ok(text.into_bytes())
        }
        Target::Hlsl => {
            use naga::back::hlsl;
            let options = hlsl::Options::default();
            let pipeline = hlsl::PipelineOptions {
                entry_point: single.then_some((stage, entry)),
            };
            let mut text = String::new();
            hlsl::Writer::new(&mut text, &options, &pipeline)
                .write(&m.module, &m.info, None)
                .map_err(|e| err(e.to_string()))?;
            Ok(text.into_bytes())
        }
    }
}
