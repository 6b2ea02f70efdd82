//! SPIR-V for exact f32: the generated WGSL compiled with naga, every float arithmetic result
//! decorated `NoContraction`, and subnormals asked to be kept.

/// SPIR-V opcodes of float arithmetic whose results are decorated `NoContraction`.
const FLOAT_ARITHMETIC: [u32; 12] = [
    127, // OpFNegate
    129, // OpFAdd
    131, // OpFSub
    133, // OpFMul
    136, // OpFDiv
    137, // OpFRem
    141, // OpFMod
    142, // OpVectorTimesScalar
    143, // OpMatrixTimesScalar
    144, // OpVectorTimesMatrix
    145, // OpMatrixTimesVector
    148, // OpDot
];
const OP_EXT_INST: u32 = 12;
const OP_TYPE_FLOAT: u32 = 22;
const OP_TYPE_VECTOR: u32 = 23;
pub(super) const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
pub(super) const NO_CONTRACTION: u32 = 42;

/// Compiles WGSL to SPIR-V 1.3 (1.4 with ray queries) with naga, all entry points, and decorates
/// every float arithmetic result `NoContraction` ([`decorate_no_contraction`]). Returns the
/// words and the number of decorations added.
pub fn spirv_no_contraction(wgsl: &str) -> Result<(Vec<u32>, usize), String> {
    let mut words = spirv(wgsl)?;
    let n = decorate_no_contraction(&mut words)?;
    Ok((words, n))
}

/// One SPIR-V instruction: its word offset, opcode and words.
type Instruction<'a> = (usize, u32, &'a [u32]);

/// A SPIR-V module's instructions after its 5-word header: (word offset, opcode, the
/// instruction's words). Errors on a module that is not SPIR-V or an instruction that runs past
/// its end.
fn instructions(words: &[u32]) -> Result<Vec<Instruction<'_>>, String> {
    if words.len() < 5 || words[0] != 0x0723_0203 {
        return Err("not a SPIR-V module".into());
    }
    let mut out = vec![];
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        if count == 0 || at + count > words.len() {
            return Err(format!("malformed SPIR-V instruction at word {at}"));
        }
        out.push((at, words[at] & 0xffff, &words[at..at + count]));
        at += count;
    }
    Ok(out)
}

const OP_EXTENSION: u32 = 10;
const OP_ENTRY_POINT: u32 = 15;
const OP_EXECUTION_MODE: u32 = 16;
const OP_CAPABILITY: u32 = 17;
const CAPABILITY_DENORM_PRESERVE: u32 = 4464;
const EXECUTION_MODE_DENORM_PRESERVE: u32 = 4459;

/// Asks for 32-bit subnormals to be kept (`SPV_KHR_float_controls`: capability
/// `DenormPreserve`, execution mode `DenormPreserve 32` on every entry point), as the CPU keeps
/// them. A driver that cannot may still flush them: the probe, compiled the same way, says
/// whether it did ([`Probe::subnormals_kept`]). Only used where the probe without it found
/// subnormals flushed and the probe with it found them kept and nothing else worse.
pub fn preserve_denormals(words: &mut Vec<u32>) -> Result<(), String> {
    let (mut after_capabilities, mut after_entry_points) = (None, None);
    let mut entries = vec![];
    for (at, op, ins) in instructions(words)? {
        match op {
            OP_CAPABILITY => after_capabilities = Some(at + ins.len()),
            OP_ENTRY_POINT => {
                entries.push(ins[2]);
                after_entry_points = Some(at + ins.len());
            }
            _ => {}
        }
    }
    let (Some(caps), Some(eps)) = (after_capabilities, after_entry_points) else {
        return Err("a SPIR-V module without capabilities or entry points".into());
    };
    let mut modes = vec![];
    for e in entries {
        modes.extend([
            (4 << 16) | OP_EXECUTION_MODE,
            e,
            EXECUTION_MODE_DENORM_PRESERVE,
            32,
        ]);
    }
    // The extension's name, NUL-terminated, in little-endian words.
    let mut name = b"SPV_KHR_float_controls".to_vec();
    name.resize(name.len() / 4 * 4 + 4, 0);
    let mut head = vec![(2 << 16) | OP_CAPABILITY, CAPABILITY_DENORM_PRESERVE];
    head.push(((1 + name.len() as u32 / 4) << 16) | OP_EXTENSION);
    head.extend(
        name.chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
    );
    // Entry points come after the capabilities: insert the later position first.
    words.splice(eps..eps, modes);
    words.splice(caps..caps, head);
    Ok(())
}

/// Compiles WGSL to SPIR-V 1.3 (1.4 with ray queries) with naga, all entry points, without any
/// `NoContraction` decoration.
pub fn spirv(wgsl: &str) -> Result<Vec<u32>, String> {
    let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| e.emit_to_string(wgsl))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default() | naga::valid::Capabilities::RAY_QUERY,
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(wgsl))?;
    let ray_query = wgsl.starts_with("enable wgpu_ray_query");
    let options = naga::back::spv::Options {
        lang_version: if ray_query { (1, 4) } else { (1, 3) },
        flags: naga::back::spv::WriterFlags::ADJUST_COORDINATE_SPACE
            | naga::back::spv::WriterFlags::LABEL_VARYINGS,
        // No binding map: each resource keeps its WGSL group and binding.
        fake_missing_bindings: true,
        bounds_check_policies: naga::proc::BoundsCheckPolicies {
            index: naga::proc::BoundsCheckPolicy::Restrict,
            buffer: naga::proc::BoundsCheckPolicy::Restrict,
            image_load: naga::proc::BoundsCheckPolicy::Restrict,
            binding_array: naga::proc::BoundsCheckPolicy::Unchecked,
        },
        ..Default::default()
    };
    naga::back::spv::write_vec(&module, &info, &options, None)
        .map_err(|e| format!("naga's SPIR-V writer: {e}"))
}

/// Adds `OpDecorate <id> NoContraction` for the result of every float arithmetic instruction
/// (OpFNegate, OpFAdd, OpFSub, OpFMul, OpFDiv, OpFRem, OpFMod, the vector and matrix products,
/// OpDot, and extended instructions — Fma, Sqrt, … — whose result is a float or float vector),
/// inserted before the module's first decoration. Returns how many were added.
pub fn decorate_no_contraction(words: &mut Vec<u32>) -> Result<usize, String> {
    let mut float_types = std::collections::HashSet::new();
    let mut targets = vec![];
    let mut first_decoration = None;
    for (at, op, ins) in instructions(words)? {
        let count = ins.len();
        match op {
            OP_TYPE_FLOAT => {
                float_types.insert(ins[1]);
            }
            OP_TYPE_VECTOR if float_types.contains(&ins[2]) => {
                float_types.insert(ins[1]);
            }
            OP_DECORATE | OP_MEMBER_DECORATE if first_decoration.is_none() => {
                first_decoration = Some(at);
            }
            _ if count >= 3
                && (FLOAT_ARITHMETIC.contains(&op) || op == OP_EXT_INST)
                && float_types.contains(&ins[1]) =>
            {
                targets.push(ins[2]);
            }
            _ => {}
        }
    }
    let at = first_decoration.ok_or("the SPIR-V module has no decorations section")?;
    let decorations: Vec<u32> = targets
        .iter()
        .flat_map(|&id| [(3 << 16) | OP_DECORATE, id, NO_CONTRACTION])
        .collect();
    words.splice(at..at, decorations);
    Ok(targets.len())
}
