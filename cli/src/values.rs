//! The values the command line's flags take, parsed and checked where they enter:
//! the library's enums by name, vectors, sizes, finite numbers, domains, byte sizes, turns, and
//! the `--domain`/`--depth` group of the commands that resample solids. Shared by the
//! subcommands (`commands/`) and the global flags (`args`).

use clap::builder::{PossibleValuesParser, TypedValueParser};
use glam::DVec3;
use octsolid::octree::{Domain, Turn};
use octsolid::shape::Axis;

/// Where a command that resamples solids puts its result: `--domain` and `--depth`
/// over the command's own default domain (`csg`: the smallest cube holding every
/// input's domain at the deepest depth; `transform`: the moved domain when the move is
/// exact, else the cube around the moved solid, at the input's depth; `convert`: the
/// input's).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct TargetFlags {
    /// The target domain MINX,MINY,MINZ,EDGE (default: the command's, see its help).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_domain)]
    pub domain: Option<[f64; 4]>,
    /// The target depth (default: the command's domain's).
    #[arg(long)]
    pub depth: Option<u8>,
}

impl TargetFlags {
    /// Whether either flag was given.
    pub(crate) fn given(&self) -> bool {
        self.domain.is_some() || self.depth.is_some()
    }

    /// The target: `--domain` (at `--depth`, else `default`'s depth), else `default` at
    /// `--depth`.
    pub(crate) fn target(&self, default: Domain) -> octsolid::Result<Domain> {
        let depth = self.depth.unwrap_or(default.depth());
        match self.domain {
            Some([x, y, z, edge]) => Domain::new(DVec3::new(x, y, z), edge, depth),
            None => default.with_depth(depth),
        }
    }
}

/// A flag's value parser for a library enum: its `names` (listed by `--help`), parsed
/// by its `FromStr` (which takes each of them).
pub(crate) fn names<T>(names: impl IntoIterator<Item = &'static str>) -> impl TypedValueParser<Value = T>
where
    T: std::str::FromStr + Clone + Send + Sync + 'static,
    T::Err: std::fmt::Debug,
{
    PossibleValuesParser::new(names).map(|s| s.parse::<T>().expect("a listed name"))
}

/// Parses `X,Y,Z`.
pub(crate) fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let v = parse_floats(s, 3)?;
    Ok([v[0], v[1], v[2]])
}

/// Parses `AXIS,DEG` (x, y or z, and an angle in degrees).
pub(crate) fn parse_turn(s: &str) -> Result<Turn, String> {
    let (axis, degrees) = s.split_once(',').ok_or_else(|| format!("'{s}' is not AXIS,DEG like z,90"))?;
    let axis = axis.trim().parse::<Axis>().map_err(|e| format!("'{s}': {e}"))?;
    let degrees = parse_floats(degrees, 1)?[0];
    Ok(Turn { axis, degrees })
}

/// Parses a signed axis, `+z`, `-x`, `y` (positive): the direction a model faces.
pub(crate) fn parse_facing(s: &str) -> Result<DVec3, String> {
    let t = s.trim();
    let (sign, name) = match t.strip_prefix('-') {
        Some(rest) => (-1.0, rest),
        None => (1.0, t.strip_prefix('+').unwrap_or(t)),
    };
    let axis = name.parse::<Axis>().map_err(|_| format!("'{s}' is not a signed axis like -z or +x"))?;
    Ok(axis.unit() * sign)
}

/// Parses `WIDTHxHEIGHT`.
pub(crate) fn parse_size(s: &str) -> Result<[u32; 2], String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("'{s}' is not a size like 960x720"))?;
    let parse = |t: &str| t.trim().parse::<u32>().map_err(|_| format!("'{t}' is not a whole number of pixels"));
    Ok([parse(w)?, parse(h)?])
}

/// Parses one finite number (`nan` and `inf` are refused where they enter).
pub(crate) fn parse_finite(s: &str) -> Result<f64, String> {
    Ok(parse_floats(s, 1)?[0])
}

/// Parses `MINX,MINY,MINZ,EDGE`.
pub(crate) fn parse_domain(s: &str) -> Result<[f64; 4], String> {
    let v = parse_floats(s, 4)?;
    Ok([v[0], v[1], v[2], v[3]])
}

fn parse_floats(s: &str, n: usize) -> Result<Vec<f64>, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|_| format!("'{t}' is not a number")))
        .collect::<Result<_, _>>()?;
    if v.len() != n {
        return Err(format!("expected {n} comma-separated numbers, got {}", v.len()));
    }
    if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
        return Err(format!("{bad} is not a finite number"));
    }
    Ok(v)
}

/// Parses a byte size such as `4096`, `512MiB`, `8GiB`, `2G` (the library's
/// [`MemoryBudget`](octsolid::MemoryBudget) parser, shared with the Python package).
pub(crate) fn parse_bytes(s: &str) -> Result<u64, String> {
    Ok(s.parse::<octsolid::MemoryBudget>()?.0)
}
