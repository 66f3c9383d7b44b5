//! The material families of `matgraph report` and their variants: which bundled graph each
//! variant is, with which variant choices and input overrides, and which variant is the
//! family's reference (its most accurate model), against which the others' error is measured.
//!
//! A variant is a bundled graph (a path relative to the graphs folder) with, optionally,
//! choices of the graph's declared `variants` (a `switch` inside one graph: the preferred
//! form, used where the family's variants are the same graph with one model swapped) and node
//! input overrides (`node.input = JSON literal`, applied to the document before it is
//! validated: for a model choice that is a node's enum or bool input, such as `pbr_brdf`'s
//! `fresnel` or `skin_single_scattering`'s `three_lobe`). Sibling graph files hold the
//! variants that differ in structure (the cartoon water baselines, the dipole skin).

/// One variant of a family.
#[derive(Clone, Copy, Debug)]
pub struct VariantSpec {
    /// Short name, unique in the family (the table's row and the plot's label).
    pub name: &'static str,
    /// The graph file, relative to the graphs folder.
    pub graph: &'static str,
    /// Choices of the graph's declared variants, `(variant, choice)`; others take defaults.
    pub choices: &'static [(&'static str, &'static str)],
    /// Node input overrides `(node id, input, JSON literal)`.
    pub set: &'static [(&'static str, &'static str, &'static str)],
    /// One line: what this variant models.
    pub doc: &'static str,
}

/// A material family: variants of one material whose cost and error are compared.
#[derive(Clone, Copy, Debug)]
pub struct Family {
    /// File-name-safe name (`docs/report/NAME.md`).
    pub name: &'static str,
    /// Title of the family's page.
    pub title: &'static str,
    /// What the family is and why its reference is the reference.
    pub doc: &'static str,
    /// Name of the reference variant (the most accurate).
    pub reference: &'static str,
    /// The variants, reference included.
    pub variants: &'static [VariantSpec],
    /// Variants named by the issue that do not exist yet: `(name, what will fill it)`.
    pub pending: &'static [(&'static str, &'static str)],
}

impl Family {
    /// The variant named `name`.
    pub fn variant(&self, name: &str) -> Option<&VariantSpec> {
        self.variants.iter().find(|v| v.name == name)
    }
}

/// A variant with no choices and no overrides: the graph as written.
const fn plain(name: &'static str, graph: &'static str, doc: &'static str) -> VariantSpec {
    VariantSpec {
        name,
        graph,
        choices: &[],
        set: &[],
        doc,
    }
}

/// Every family of the report, in the order of `docs/report/README.md`.
pub const FAMILIES: &[Family] = &[
    Family {
        name: "skin",
        title: "Skin (seed 001)",
        doc: "The 2004 Maya skin shader on the material ball. Reference: the epidermis from \
              Jensen et al. 2001's dipole, the only variant that models multiple scattering \
              physically (the paper fakes it).",
        reference: "dipole",
        variants: &[
            plain(
                "paper_fake",
                "skin.json",
                "the paper as written: one Hanrahan–Krueger lobe (g = 0.8), faked multiple scattering",
            ),
            VariantSpec {
                name: "three_lobes",
                graph: "skin.json",
                choices: &[],
                set: &[("ss", "three_lobe", "true")],
                doc: "single scattering summed over Pharr's three lobes instead of one",
            },
            plain(
                "dipole",
                "skin_dipole.json",
                "the epidermis from Jensen et al. 2001's dipole diffusion",
            ),
        ],
        pending: &[],
    },
    Family {
        name: "pbr",
        title: "PBR glass (seed 003)",
        doc: "Glass (n = 1.52) in the metallic–roughness model (GGX, height-correlated Smith) \
              on the material ball, its environment reflection by image-based lighting \
              (docs/models/ibl.md). Reference: the exact dielectric Fresnel equations in the \
              BRDF and the environment's specular reflection by Monte Carlo integration \
              (env_ggx_monte_carlo, 64 GGX-importance-sampled directions over the raw map, the \
              same exact Fresnel), the split sum's own reference.",
        reference: "mc_exact",
        variants: &[
            plain(
                "schlick",
                "pbr_glass.json",
                "Schlick's Fresnel in pbr_brdf, split-sum image-based lighting (as bundled)",
            ),
            VariantSpec {
                name: "exact_fresnel",
                graph: "pbr_glass.json",
                choices: &[],
                set: &[("brdf", "fresnel", "\"exact\"")],
                doc: "the exact dielectric Fresnel equations in pbr_brdf, split-sum image-based lighting",
            },
            VariantSpec {
                name: "mc_schlick",
                graph: "pbr_glass.json",
                choices: &[("ibl", "monte_carlo")],
                set: &[],
                doc: "Schlick's Fresnel, the environment's specular by env_ggx_monte_carlo (64 samples) instead of the split sum",
            },
            VariantSpec {
                name: "mc_exact",
                graph: "pbr_glass.json",
                choices: &[("ibl", "monte_carlo")],
                set: &[
                    ("brdf", "fresnel", "\"exact\""),
                    ("env_mc", "fresnel", "\"exact\""),
                ],
                doc: "exact Fresnel in pbr_brdf and env_ggx_monte_carlo (64 samples) for the environment's specular",
            },
        ],
        pending: &[],
    },
    Family {
        name: "bubble",
        title: "Soap bubble (seed 000)",
        doc: "A soap film (n = 1.33, 200–800 nm) in the bubble scene. Reference: the thin film's \
              spectral method (471 wavelengths, D65 × CIE 1931). The paper's vector d·R + d·T \
              is a colour made from directions, not a film, so its error is large by design.",
        reference: "spectral",
        variants: &[
            plain(
                "paper_vector",
                "bubble.json",
                "seed 000 as written: the Snell/TIR vector d·R + d·T as colour",
            ),
            VariantSpec {
                name: "spectral",
                graph: "bubble_iridescent.json",
                choices: &[("thin_film", "spectral")],
                set: &[],
                doc: "thin_film, spectral: Σ over 360–830 nm at 1 nm",
            },
            VariantSpec {
                name: "belcour_barla",
                graph: "bubble_iridescent.json",
                choices: &[("thin_film", "belcour_barla")],
                set: &[],
                doc: "thin_film, Belcour & Barla 2017's analytic spectral integration",
            },
            VariantSpec {
                name: "rgb3",
                graph: "bubble_iridescent.json",
                choices: &[("thin_film", "rgb3")],
                set: &[],
                doc: "thin_film at three wavelengths (R, G, B)",
            },
            VariantSpec {
                name: "table",
                graph: "bubble_iridescent.json",
                choices: &[("thin_film", "table")],
                set: &[],
                doc: "thin_film, the Airy sum's Fourier series through the tabulated cosine transform of the spectral weights",
            },
        ],
        pending: &[],
    },
    Family {
        name: "sunshine",
        title: "Super Mario Sunshine water (seed 002)",
        doc: "The Sunshine water in its water scene. Reference: the variant with the exact \
              Fresnel mix of refraction and reflection (the faithful one uses the game's \
              constant blend).",
        reference: "fresnel",
        variants: &[
            plain(
                "faithful",
                "water_sunshine.json",
                "the game's water as re-implemented in seed 002",
            ),
            plain(
                "fresnel",
                "water_sunshine_fresnel.json",
                "the same with the exact Fresnel reflectance",
            ),
        ],
        pending: &[],
    },
    Family {
        name: "cartoon_water",
        title: "Cartoon water (seed 004)",
        doc: "Environment-adaptive cartoon water at day in its water scene. Reference: the \
              paper's water with the Beer–Lambert depth colour, the physically based law for \
              light absorbed with depth.",
        reference: "beer_lambert",
        variants: &[
            plain(
                "paper",
                "water_toon_day.json",
                "seed 004 as written: depth colour after the atmosphere, toon Blinn–Phong, maps, Fresnel",
            ),
            plain(
                "beer_lambert",
                "water_toon_beer_lambert.json",
                "the paper's water with the Beer–Lambert depth colour",
            ),
            plain(
                "eden",
                "water_toon_eden.json",
                "baseline: Eden et al., toon shading of one blue",
            ),
            plain(
                "you",
                "water_toon_you.json",
                "baseline: You et al., toon shading with maps, one blue",
            ),
        ],
        pending: &[],
    },
];

/// The family named `name`.
pub fn family(name: &str) -> Option<&'static Family> {
    FAMILIES.iter().find(|f| f.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_reference_is_a_variant_and_names_are_unique() {
        for f in FAMILIES {
            assert!(f.variant(f.reference).is_some(), "{}", f.name);
            let mut names: Vec<&str> = f.variants.iter().map(|v| v.name).collect();
            names.extend(f.pending.iter().map(|p| p.0));
            let n = names.len();
            names.sort();
            names.dedup();
            assert_eq!(names.len(), n, "{}", f.name);
        }
    }
}
