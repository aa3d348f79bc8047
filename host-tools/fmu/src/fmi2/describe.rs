//! The FMI 2.0 `modelDescription.xml` of each FMU, from the same variables
//! as the 3.0 one ([`crate::describe`]: names, value references,
//! descriptions, units, ranges, dependencies), in 2.0's form: `guid` (the
//! 3.0 instantiation token, which `fmi2Instantiate` checks), one
//! `ScalarVariable` per variable (no `time`; `flags` as `Integer`, FMI 2.0
//! has no unsigned type), `ModelStructure` with `Outputs` and
//! `InitialUnknowns` (no `Derivatives`: the models have no continuous
//! state), `numberOfEventIndicators`.
//!
//! Written as text rather than through fmi-schema's `fmi2` types: those
//! write the empty `<Derivatives>` element, which the FMI 2.0 schema
//! refuses (it needs at least one `Unknown`).
use crate::describe::{unit_of, Describe, Kind};
use fmi::schema::fmi3::{Causality, Variability, Variable};
use fmi_export::fmi3::Model;
use std::fmt::Write as _;

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

fn causality(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::CalculatedParameter => "calculatedParameter",
        Causality::Input => "input",
        Causality::Output => "output",
        Causality::Independent => "independent",
        _ => "local",
    }
}

fn variability(v: Variability) -> &'static str {
    match v {
        Variability::Constant => "constant",
        Variability::Fixed => "fixed",
        Variability::Tunable => "tunable",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    }
}

/// `kind`'s model description for FMI 2.0, as XML.
pub fn model_description(kind: Kind, describe: &Describe) -> Result<String, String> {
    let (meta, token, event_indicators, model_exchange) = match kind {
        Kind::Damper => (
            <crate::Damper as Model>::build_toplevel_metadata(),
            <crate::Damper as Model>::INSTANTIATION_TOKEN,
            <crate::Damper as Model>::MAX_EVENT_INDICATORS,
            true,
        ),
        Kind::Controller => (
            <crate::Controller as Model>::build_toplevel_metadata(),
            <crate::Controller as Model>::INSTANTIATION_TOKEN,
            <crate::Controller as Model>::MAX_EVENT_INDICATORS,
            false,
        ),
    };
    let dependencies = crate::describe::dependencies(kind);
    let mut used = Vec::new();
    let mut scalars = String::new();
    // (index in ModelVariables, 1-based; value reference; causality)
    let mut listed: Vec<(usize, u32, Causality)> = Vec::new();
    for v in meta.model_variables.variables.iter() {
        let (element, vr, name, description, c, var, start, initial_calculated) = match v {
            Variable::Float64(f) => (
                "Real",
                f.value_reference,
                &f.name,
                f.description.as_deref(),
                f.causality.unwrap_or_default(),
                f.variability.unwrap_or(Variability::Continuous),
                f.start.as_ref().and_then(|s| s.0.first().copied()),
                f.initial.is_some(),
            ),
            Variable::UInt32(f) => (
                "Integer",
                f.value_reference,
                &f.name,
                f.description.as_deref(),
                f.causality.unwrap_or_default(),
                f.variability.unwrap_or(Variability::Discrete),
                f.start.as_ref().and_then(|s| s.0.first().map(|x| f64::from(*x))),
                f.initial.is_some(),
            ),
            _ => return Err("internal: a variable type FMI 2.0 export does not handle".to_string()),
        };
        if c == Causality::Independent {
            continue;
        }
        listed.push((listed.len() + 1, vr, c));
        let mut attrs = String::new();
        if element == "Real" {
            let unit = unit_of(name).ok_or_else(|| format!("internal: variable {name} has no unit suffix"))?;
            write!(attrs, " declaredType=\"{}\"", unit.1).ok();
            if let Some(r) = describe.ranges.iter().find(|r| r.name == name) {
                write!(attrs, " min=\"{:e}\" max=\"{:e}\"", r.min, r.max).ok();
            }
            if !used.contains(&unit) {
                used.push(unit);
            }
        }
        // FMI 2.0 §2.2.7: an input has a start and no initial; a calculated
        // output, local or calculated parameter has initial="calculated" and no start.
        let initial = if c == Causality::Input {
            if let Some(s) = start {
                write!(attrs, " start=\"{s:e}\"").ok();
            }
            ""
        } else if initial_calculated || matches!(c, Causality::Output | Causality::CalculatedParameter) {
            " initial=\"calculated\""
        } else {
            ""
        };
        write!(
            scalars,
            "    <ScalarVariable name=\"{}\" valueReference=\"{vr}\"{} causality=\"{}\" variability=\"{}\"{initial}>\n      <{element}{attrs}/>\n    </ScalarVariable>\n",
            escape(name),
            description.map_or_else(String::new, |d| format!(" description=\"{}\"", escape(d))),
            causality(c),
            variability(var),
        )
        .ok();
    }
    // The time variable's unit too (the default experiment is in seconds).
    let units = used
        .iter()
        .map(|(_, _, unit, [kg, m, s, a])| {
            let mut base = String::new();
            for (name, e) in [("kg", kg), ("m", m), ("s", s), ("A", a)] {
                if *e != 0 {
                    write!(base, " {name}=\"{e}\"").ok();
                }
            }
            format!(
                "    <Unit name=\"{}\">\n      <BaseUnit{base}/>\n    </Unit>\n",
                escape(unit)
            )
        })
        .collect::<String>();
    let types = used
        .iter()
        .map(|(suffix, name, unit, _)| {
            let nominal = describe
                .nominal(suffix)
                .map_or_else(String::new, |n| format!(" nominal=\"{n:e}\""));
            format!(
                "    <SimpleType name=\"{name}\">\n      <Real quantity=\"{name}\" unit=\"{}\"{nominal}/>\n    </SimpleType>\n",
                escape(unit)
            )
        })
        .collect::<String>();
    let index_of = |vr: u32| listed.iter().find(|(_, v, _)| *v == vr).map(|(i, _, _)| *i);
    let unknown = |index: usize, vr: u32| {
        let deps: Vec<usize> = dependencies
            .iter()
            .find(|(v, _)| *v == vr)
            .map(|(_, d)| d.iter().filter_map(|d| index_of(*d)).collect())
            .unwrap_or_default();
        let kinds = if deps.is_empty() {
            String::new()
        } else {
            format!(
                " dependenciesKind=\"{}\"",
                deps.iter().map(|_| "dependent").collect::<Vec<_>>().join(" ")
            )
        };
        format!(
            "      <Unknown index=\"{index}\" dependencies=\"{}\"{kinds}/>\n",
            deps.iter().map(|d| d.to_string()).collect::<Vec<_>>().join(" ")
        )
    };
    let outputs: String = listed
        .iter()
        .filter(|(_, _, c)| *c == Causality::Output)
        .map(|(i, vr, _)| unknown(*i, *vr))
        .collect();
    // Outputs and calculated parameters are computed in Initialization Mode.
    let initial_unknowns: String = listed
        .iter()
        .filter(|(_, _, c)| matches!(c, Causality::Output | Causality::CalculatedParameter))
        .map(|(i, vr, _)| unknown(*i, *vr))
        .collect();
    let id = kind.model_identifier();
    let me = if model_exchange {
        format!(
            "  <ModelExchange modelIdentifier=\"{id}\" canNotUseMemoryManagementFunctions=\"true\" \
             canGetAndSetFMUstate=\"false\" canSerializeFMUstate=\"false\" completedIntegratorStepNotNeeded=\"true\"/>\n"
        )
    } else {
        String::new()
    };
    let date = describe
        .generation_date_and_time
        .as_deref()
        .map_or_else(String::new, |d| format!("\n  generationDateAndTime=\"{}\"", escape(d)));
    Ok(format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription
  fmiVersion="2.0"
  modelName="{model_name}"
  guid="{token}"
  description="{description}"
  version="{version}"
  generationTool="{tool}"{date}
  license="MIT OR Apache-2.0"
  variableNamingConvention="flat"
  numberOfEventIndicators="{event_indicators}">
{me}  <CoSimulation modelIdentifier="{id}" canHandleVariableCommunicationStepSize="true" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="false" canSerializeFMUstate="false"/>
  <UnitDefinitions>
{units}  </UnitDefinitions>
  <TypeDefinitions>
{types}  </TypeDefinitions>
  <DefaultExperiment startTime="0" stopTime="{stop:e}" stepSize="{step:e}"/>
  <ModelVariables>
{scalars}  </ModelVariables>
  <ModelStructure>
    <Outputs>
{outputs}    </Outputs>
    <InitialUnknowns>
{initial_unknowns}    </InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>
"#,
        model_name = escape(&describe.model_name),
        token = escape(token),
        description = escape(&describe.description),
        version = escape(&describe.version),
        tool = escape(&describe.generation_tool),
        stop = describe.stop_time_s,
        step = describe.step_size_s,
    ))
}
