//! What the driver's shader compiler made of each pipeline, through
//! `VK_KHR_pipeline_executable_properties`: per executable (a compiled shader stage) the
//! statistics the driver names (Mesa's turnip, for Adreno: instruction count, registers, waves,
//! instruction categories, sync stalls; see `render::budget::adreno`). Captured only when
//! [`ContextOptions::capture_statistics`](super::ContextOptions) asks (`vr-ocean
//! shader-stats`), for every pipeline made through the context, under the label its maker gave.

use std::sync::Mutex;

use ash::vk;

use super::error::RenderError;

/// One statistic's value, in the format the driver reports it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum StatValue {
    /// A flag.
    Bool(bool),
    /// A signed integer.
    Int(i64),
    /// An unsigned integer (counts).
    Uint(u64),
    /// A real number.
    Float(f64),
}

impl StatValue {
    /// The value as a number (a flag as 0 or 1).
    pub fn as_f64(self) -> f64 {
        match self {
            StatValue::Bool(b) => f64::from(u8::from(b)),
            StatValue::Int(i) => i as f64,
            StatValue::Uint(u) => u as f64,
            StatValue::Float(f) => f,
        }
    }
}

/// One named statistic.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Statistic {
    /// The driver's name for it ("Instruction Count").
    pub name: String,
    /// Its value.
    pub value: StatValue,
}

/// One executable of a pipeline: a shader stage as the driver compiled it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Executable {
    /// "vertex" or "fragment" (others by their Vulkan flags).
    pub stage: String,
    /// The driver's name for it.
    pub name: String,
    /// Its statistics, in the driver's order.
    pub statistics: Vec<Statistic>,
}

impl Executable {
    /// The statistic called `name`, as a number.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.statistics
            .iter()
            .find(|s| s.name == name)
            .map(|s| s.value.as_f64())
    }
}

/// A pipeline's executables, under its maker's label ("ocean", "solids", "panel").
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PipelineStatistics {
    /// What the pipeline draws.
    pub label: String,
    /// Its executables.
    pub executables: Vec<Executable>,
}

/// The statistics of every pipeline made while the context captured them.
#[derive(Debug, Default)]
pub struct StatisticsLog {
    pipelines: Mutex<Vec<PipelineStatistics>>,
}

impl StatisticsLog {
    /// Reads `pipeline`'s executables and their statistics (it was created with
    /// `CAPTURE_STATISTICS` on `device`, of `instance`) and files them under `label`.
    pub fn record(
        &self,
        instance: &ash::Instance,
        device: &ash::Device,
        label: &str,
        pipeline: vk::Pipeline,
    ) -> Result<(), RenderError> {
        let ext = ash::khr::pipeline_executable_properties::Device::new(instance, device);
        let info = vk::PipelineInfoKHR::default().pipeline(pipeline);
        // SAFETY: the pipeline is alive and was created with CAPTURE_STATISTICS on a device
        // with `pipelineExecutableInfo` enabled (the context only captures then).
        let props = unsafe { ext.get_pipeline_executable_properties(&info) }
            .map_err(RenderError::vk("vkGetPipelineExecutablePropertiesKHR"))?;
        let mut executables = Vec::with_capacity(props.len());
        for (i, p) in props.iter().enumerate() {
            let exe = vk::PipelineExecutableInfoKHR::default()
                .pipeline(pipeline)
                .executable_index(i as u32);
            // SAFETY: `i` is one of the pipeline's executables.
            let stats = unsafe { ext.get_pipeline_executable_statistics(&exe) }
                .map_err(RenderError::vk("vkGetPipelineExecutableStatisticsKHR"))?;
            executables.push(Executable {
                stage: stage_name(p.stages),
                name: p
                    .name_as_c_str()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                statistics: stats.iter().map(statistic).collect(),
            });
        }
        if let Ok(mut all) = self.pipelines.lock() {
            all.push(PipelineStatistics {
                label: label.to_string(),
                executables,
            });
        }
        Ok(())
    }

    /// Everything captured so far, in the order the pipelines were made.
    pub fn pipelines(&self) -> Vec<PipelineStatistics> {
        self.pipelines.lock().map(|p| p.clone()).unwrap_or_default()
    }
}

/// A statistic as the driver wrote it.
fn statistic(s: &vk::PipelineExecutableStatisticKHR) -> Statistic {
    use vk::PipelineExecutableStatisticFormatKHR as F;
    // SAFETY: the driver wrote the union member that `format` names.
    let value = unsafe {
        match s.format {
            F::BOOL32 => StatValue::Bool(s.value.b32 != 0),
            F::INT64 => StatValue::Int(s.value.i64),
            F::FLOAT64 => StatValue::Float(s.value.f64),
            _ => StatValue::Uint(s.value.u64),
        }
    };
    Statistic {
        name: s
            .name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        value,
    }
}

/// "vertex", "fragment", or the flags' debug name for other stages.
fn stage_name(stages: vk::ShaderStageFlags) -> String {
    if stages == vk::ShaderStageFlags::VERTEX {
        "vertex".into()
    } else if stages == vk::ShaderStageFlags::FRAGMENT {
        "fragment".into()
    } else {
        format!("{stages:?}").to_lowercase()
    }
}
