//! pelt-fur: fur textures from one seeded strand model.
//!
//! One set of strands ([`strands`]) on a tileable square is rendered three ways, so that the
//! textures agree strand for strand (as Lengyel et al. derive shell and fin textures from one
//! hair model):
//!
//! - [`raster`]: from above, the **dot texture** (anti-aliased coverage, Frantzen's "dots") and
//!   the **heightfield** Revie's shells fade against with smoothstep (§2.4.1, §2.4.4);
//! - [`fin`]: from the side, the **fin texture** for silhouette fins;
//! - [`mips`]: **coverage-preserving mip chains**, so fur seen from afar keeps its density.
//!
//! [`flags`] holds the strand model as `pelt textures` flags (clap `Args` with the `cli`
//! feature). [`density`] holds the same strands as a medium (the area of strands taller than each
//! height, with mips) for the shells' sub-pixel coverage, [`path`] the curve every strand
//! follows (Revie Listing 2.1) and its tangent. [`expect`] holds the analytic coverage the tests measure against, [`image`] the PNG
//! encoding, [`manifest`] the fur parameters written beside the textures or into a `.glb`.

pub mod density;
pub mod error;
pub mod expect;
pub mod fin;
pub mod flags;
pub mod image;
pub mod manifest;
pub mod mips;
pub mod params;
pub mod path;
pub mod raster;
pub mod rng;
pub mod set;
pub mod shells;
pub mod strands;

pub use error::{FurError, ParamError};
pub use image::{Image, Pixels};
pub use manifest::{FurConfig, FurManifest};
pub use params::{HeightBits, StrandParams};
pub use set::{TextureSet, generate};
