//! `modelDescription.xml` of each FMU: the variables rust-fmi's derive
//! builds, plus what the derive cannot say (fmi-export 0.3's `#[variable]`
//! has no unit, and fmi-schema 0.8's `Float64` variable no `unit`
//! attribute): every float variable gets a declared type whose unit is the
//! SI unit its name ends in, with the unit definitions, the interface
//! elements and a default experiment. Every unit has its `BaseUnit` (the
//! ampere's exponent written `A`, as FMI 3.0 names it, by the workspace's
//! fmi-schema copy: host-tools/fmu/fmi-schema/PATCHED.md). Inputs carry
//! `min`/`max` ([`crate::ranges`]); their quantities' types a `nominal`.
use fmi::schema::fmi3::{
    BaseUnit, DefaultExperiment, Float64Type, Fmi3CoSimulation, Fmi3ModelDescription, Fmi3ModelExchange, Fmi3Unit,
    TypeDefinition, TypeDefinitions, UnitDefinitions, Variable,
};
use fmi_export::fmi3::Model;

/// Which FMU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Damper,
    Controller,
}

impl Kind {
    /// The FMU's model identifier: its shared library's name without prefix
    /// and extension (the `cdylib` name).
    pub fn model_identifier(self) -> &'static str {
        match self {
            Kind::Damper => "mre_damper",
            Kind::Controller => "mre_controller",
        }
    }

    /// `damper` or `controller` (the file stem `mre fmu` writes).
    pub fn stem(self) -> &'static str {
        match self {
            Kind::Damper => "damper",
            Kind::Controller => "controller",
        }
    }
}

/// Unit of a variable from its name's suffix (longest first), as
/// `(suffix, declared type, unit, SI base exponents kg, m, s, A)`.
pub(crate) const UNITS: [(&str, &str, &str, [i32; 4]); 8] = [
    ("_m_s", "Velocity", "m/s", [0, 1, -1, 0]),
    ("_kg", "Mass", "kg", [1, 0, 0, 0]),
    ("_m", "Length", "m", [0, 1, 0, 0]),
    ("_s", "Time", "s", [0, 0, 1, 0]),
    ("_a", "Current", "A", [0, 0, 0, 1]),
    ("_n", "Force", "N", [1, 1, -2, 0]),
    ("_v", "Voltage", "V", [1, 2, -3, -1]),
    ("_ohm", "Resistance", "Ohm", [1, 2, -3, -2]),
];

pub(crate) fn unit_of(name: &str) -> Option<&'static (&'static str, &'static str, &'static str, [i32; 4])> {
    UNITS.iter().find(|(suffix, ..)| name.ends_with(suffix))
}

/// The inputs every output of `kind` depends on directly, by name: the
/// damper's force is a function of all three; the controller's outputs hold
/// between communication points (they change in `doStep` only), so at a
/// communication point they depend on none.
fn output_depends_on(kind: Kind) -> &'static [&'static str] {
    match kind {
        Kind::Damper => &["displacement_m", "velocity_m_s", "current_a"],
        Kind::Controller => &[],
    }
}

fn metadata(kind: Kind) -> fmi_export::fmi3::ModelMetadata {
    match kind {
        Kind::Damper => <crate::Damper as Model>::build_toplevel_metadata(),
        Kind::Controller => <crate::Controller as Model>::build_toplevel_metadata(),
    }
}

/// The model structure with each output's dependencies declared (fmi-export
/// declares none, which FMI 3.0 reads as "depends on every known").
fn model_structure(
    kind: Kind,
    variables: &fmi::schema::fmi3::ModelVariables,
    mut structure: fmi::schema::fmi3::ModelStructure,
) -> fmi::schema::fmi3::ModelStructure {
    use fmi::schema::fmi3::{DependenciesKind, VariableDependency};
    use fmi::schema::utils::AttrList;
    let vrs: Vec<u32> = output_depends_on(kind)
        .iter()
        .filter_map(|name| {
            variables
                .iter_abstract()
                .find(|v| v.name() == *name)
                .map(|v| v.value_reference())
        })
        .collect();
    for unknown in structure.unknowns.iter_mut() {
        if let VariableDependency::Output(u) = unknown {
            u.dependencies = Some(AttrList(vrs.clone()));
            u.dependencies_kind = Some(AttrList(vrs.iter().map(|_| DependenciesKind::Dependent).collect()));
        }
    }
    structure
}

/// Each output's value reference and those of the knowns it depends on, as
/// the model description declares them.
pub fn dependencies(kind: Kind) -> Vec<(u32, Vec<u32>)> {
    use fmi::schema::fmi3::VariableDependency;
    let meta = metadata(kind);
    model_structure(kind, &meta.model_variables, meta.model_structure)
        .unknowns
        .iter()
        .filter_map(|u| match u {
            VariableDependency::Output(u) => Some((
                u.value_reference,
                u.dependencies.as_ref().map(|d| d.0.clone()).unwrap_or_default(),
            )),
            _ => None,
        })
        .collect()
}

/// What the XML says besides the variables.
#[derive(Clone, Debug)]
pub struct Describe {
    /// The model's name and a one-line description (with the model file's provenance).
    pub model_name: String,
    pub description: String,
    /// Default experiment: stop time and step (s).
    pub stop_time_s: f64,
    pub step_size_s: f64,
    /// The inputs' declared ranges (`min`, `max`; `nominal` on their types).
    pub ranges: Vec<crate::ranges::InputRange>,
    /// The FMU's `version` and `generationTool`.
    pub version: String,
    pub generation_tool: String,
    /// `generationDateAndTime` (ISO 8601, UTC).
    pub generation_date_and_time: Option<String>,
}

impl Describe {
    /// The nominal of the quantity whose unit suffix is `suffix`: the first
    /// input of that quantity's (it goes on the type, shared by 3.0 and 2.0).
    pub fn nominal(&self, suffix: &str) -> Option<f64> {
        self.ranges
            .iter()
            .find(|r| unit_of(r.name).is_some_and(|u| u.0 == suffix))
            .map(|r| r.nominal)
    }
}

/// The model description of `kind`, as XML.
pub fn model_description(kind: Kind, describe: &Describe) -> Result<String, String> {
    let meta = metadata(kind);
    let structure = model_structure(kind, &meta.model_variables, meta.model_structure);
    let token = match kind {
        Kind::Damper => <crate::Damper as Model>::INSTANTIATION_TOKEN,
        Kind::Controller => <crate::Controller as Model>::INSTANTIATION_TOKEN,
    };
    let mut variables = meta.model_variables;
    let mut used: Vec<&(&str, &str, &str, [i32; 4])> = Vec::new();
    for v in variables.variables.iter_mut() {
        if let Variable::Float64(f) = v {
            if f.name == "time" {
                continue;
            }
            let unit = unit_of(&f.name).ok_or_else(|| format!("internal: variable {} has no unit suffix", f.name))?;
            f.declared_type = Some(unit.1.to_string());
            if let Some(r) = describe.ranges.iter().find(|r| r.name == f.name) {
                f.min = Some(r.min);
                f.max = Some(r.max);
            }
            if !used.contains(&unit) {
                used.push(unit);
            }
        }
    }
    // The independent variable `time` in seconds too.
    let time = unit_of("time_s");
    for v in variables.variables.iter_mut() {
        if let (Variable::Float64(f), Some(unit)) = (v, time) {
            if f.name == "time" {
                f.declared_type = Some(unit.1.to_string());
                if !used.contains(&unit) {
                    used.push(unit);
                }
            }
        }
    }
    let units = used
        .iter()
        .map(|(_, _, unit, [kg, m, s, a])| Fmi3Unit {
            name: (*unit).to_string(),
            base_unit: Some(BaseUnit {
                kg: (*kg != 0).then_some(*kg),
                m: (*m != 0).then_some(*m),
                s: (*s != 0).then_some(*s),
                a: (*a != 0).then_some(*a),
                ..Default::default()
            }),
            ..Default::default()
        })
        .collect();
    let types = used
        .iter()
        .map(|(suffix, name, unit, _)| {
            // An input's nominal on its quantity's type (fmi-schema's variable has no `nominal`).
            let nominal = describe.nominal(suffix);
            TypeDefinition::Float64(Float64Type {
                name: (*name).to_string(),
                quantity: Some((*name).to_string()),
                unit: Some((*unit).to_string()),
                nominal,
                ..Default::default()
            })
        })
        .collect();
    let id = kind.model_identifier().to_string();
    let md = Fmi3ModelDescription {
        fmi_version: "3.0".to_string(),
        model_name: describe.model_name.clone(),
        instantiation_token: token.to_string(),
        description: Some(describe.description.clone()),
        version: Some(describe.version.clone()),
        generation_tool: Some(describe.generation_tool.clone()),
        generation_date_and_time: describe.generation_date_and_time.clone(),
        license: Some("MIT OR Apache-2.0".to_string()),
        model_exchange: (kind == Kind::Damper).then(|| Fmi3ModelExchange {
            model_identifier: id.clone(),
            can_get_and_set_fmu_state: Some(false),
            can_serialize_fmu_state: Some(false),
            ..Default::default()
        }),
        co_simulation: Some(Fmi3CoSimulation {
            model_identifier: id,
            can_handle_variable_communication_step_size: Some(true),
            fixed_internal_step_size: (kind == Kind::Controller).then_some(describe.step_size_s),
            has_event_mode: Some(false),
            can_get_and_set_fmu_state: Some(false),
            can_serialize_fmu_state: Some(false),
            ..Default::default()
        }),
        unit_definitions: Some(UnitDefinitions { units }),
        type_definitions: Some(TypeDefinitions {
            type_definitions: types,
        }),
        default_experiment: Some(DefaultExperiment {
            start_time: Some(0.0),
            stop_time: Some(describe.stop_time_s),
            step_size: Some(describe.step_size_s),
            ..Default::default()
        }),
        model_variables: variables,
        model_structure: structure,
        ..Default::default()
    };
    fmi::schema::serialize(&md, false).map_err(|e| format!("cannot write the model description: {e}"))
}

/// One variable as the documentation lists it.
#[derive(Clone, Debug)]
pub struct Listed {
    pub name: String,
    /// `input`, `output` or `calculatedParameter`.
    pub causality: &'static str,
    /// The SI unit (`flags` has none).
    pub unit: Option<&'static str>,
    pub description: String,
}

/// `kind`'s variables in value-reference order, without the independent `time`.
pub fn variables(kind: Kind) -> Vec<Listed> {
    use fmi::schema::fmi3::Causality;
    metadata(kind)
        .model_variables
        .iter_abstract()
        .filter(|v| v.name() != "time")
        .map(|v| Listed {
            name: v.name().to_owned(),
            causality: match v.causality() {
                Causality::Input => "input",
                Causality::Output => "output",
                Causality::CalculatedParameter => "calculatedParameter",
                Causality::Parameter => "parameter",
                _ => "local",
            },
            unit: unit_of(v.name()).map(|u| u.2),
            description: v.description().unwrap_or_default().to_owned(),
        })
        .collect()
}
