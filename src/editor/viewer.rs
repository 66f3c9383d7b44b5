//! The canvas viewer (egui-snarl's [`SnarlViewer`]): node headers coloured by category, pins
//! by socket type (generic pins square), values edited in place. It only reads the document
//! and queues [`Action`]s, which the app applies after the frame through the state's edits.

use super::cull::{Culling, Wire};
use super::entry::Rejections;
use super::handoff::POINTER_REACH;
use super::layout::HEADER_HEIGHT;
use super::model::EditorDoc;
use super::outputs::{OUTPUT_NODE, OUTPUT_TITLE, STANDARD, note};
use super::overview::{Body, Overview, pin_shape};
use super::params;
use super::pin_tips::{PinRows, tip};
use super::ports::Kind;
use super::scope::{GROUP_OUTPUT_TITLE, GROUP_PANEL, INPUT_NODE, INPUT_TITLE};
use super::search::WireFilter;
use super::stand_in::{LookKey, Looks};
use super::view::{GENERIC_UNKNOWN, NodeView, category_color, socket_color};
use super::widgets::{current_lanes, value_editor_checked};
use crate::node::PortType;
use egui::{Color32, Shape, Stroke, Ui};
use egui_snarl::ui::{AnyPins, BackgroundPattern, PinInfo, PinShape, SnarlStyle, SnarlViewer};
use egui_snarl::{InPin, NodeId, OutPin, Snarl};

/// What the user asked for on the canvas during a frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Link an output to an input.
    Connect {
        /// Source node id.
        from: String,
        /// Source output name.
        output: String,
        /// Target node id.
        to: String,
        /// Target input name.
        input: String,
    },
    /// Remove the link of an input.
    Disconnect {
        /// Node id.
        node: String,
        /// Input name.
        input: String,
    },
    /// Write literals on several inputs of one node in one undo step (the ramp-and-curve
    /// widget, [`super::ramp_ui`]); steps with the same `key` coalesce (one drag).
    SetInputs {
        /// Node id.
        node: String,
        /// (input name, literal) pairs.
        values: super::ramps::Edits,
        /// The coalescing key.
        key: Option<String>,
    },
    /// Write a literal on an input (coalesced per input while the pointer is held).
    SetInput {
        /// Node id.
        node: String,
        /// Input name.
        input: String,
        /// The literal.
        value: serde_json::Value,
    },
    /// Open the add-node search at a canvas position, for a wire dropped there.
    Search {
        /// Canvas position.
        pos: [f32; 2],
        /// The dropped wire: its node id, port name, and what the new node must offer.
        wire: Option<(String, String, WireFilter)>,
    },
    /// Show this node in the side panel.
    Focus(String),
    /// Delete these nodes.
    Remove(Vec<String>),
    /// Duplicate these nodes.
    Duplicate(Vec<String>),
    /// Turn this node's preview swatch on or off.
    TogglePreview(String),
    /// Show this node's output in the main preview ("Preview this output",
    /// Ctrl+Shift+click), or (`None`) the graph's outputs again; the file is unchanged.
    PreviewOutput(Option<String>),
    /// Add a graph output (a pin of the Material Output node).
    AddOutput(String),
    /// Rename a graph output.
    RenameOutput {
        /// Its name.
        old: String,
        /// The new name.
        new: String,
    },
    /// Remove a graph output.
    RemoveOutput(String),
    /// Expose an input as a parameter ([`super::params::expose`]).
    Expose {
        /// Node id.
        node: String,
        /// Input name.
        input: String,
        /// The parameter's name (`None`: the input's, made unique).
        name: Option<String>,
    },
    /// Un-expose a parameter, keeping its value on the inputs it fed.
    Unexpose(String),
    /// List an unlisted `parameter` node in the graph's parameters.
    ListParameter(String),
    /// Enter this group instance's group (Tab).
    EnterGroup(String),
    /// Ungroup this group instance (Alt+G).
    Ungroup(String),
    /// Group the selected nodes (Ctrl+G).
    GroupSelected,
    /// A value typed into an input's editor was refused ([`super::entry::check`]): the
    /// graph is unchanged.
    Reject {
        /// Node id.
        node: String,
        /// Input name.
        input: String,
        /// Why.
        why: String,
    },
    /// Pick a texture node's image, or set its colour space ([`super::textures`]).
    Texture(super::textures::TextureAction),
    /// Run a node command from this node's menu ([`super::node_commands`]): on the
    /// selection when the node is in it, else on the node.
    Command(super::keymap::NodeCommand, String),
}

/// What a node's preview swatch shows under its pins.
#[derive(Clone, Debug, PartialEq)]
pub enum Swatch {
    /// The rendered swatch.
    Image(egui::TextureId),
    /// Why it could not be rendered.
    Message(String),
    /// Not rendered yet.
    Pending,
}

/// Side of a node's swatch on the canvas, points (before the canvas zoom).
pub const NODE_SWATCH_POINTS: f32 = 96.0;

/// Below this canvas zoom the canvas is an overview ([`super::overview`]), as Unreal's
/// graph editor drops detail when zoomed out: the pins' names and value editors would be
/// under 4 px, and laying out the widgets of every node and pin was most of the frame of a
/// large graph framed whole (benches/editor.rs). The headers (the node's id and its error
/// mark, painted without widgets; not the preview toggle) stay, and the pins and wires are
/// painted; wires are made and removed zoomed in.
pub const LOW_DETAIL_ZOOM: f32 = 0.3;

/// Canvas points between a node's estimated width ([`super::layout::node_size`]) and its overview body's:
/// the node frame's margins and the spacing beside the body.
const BODY_INSET: f32 = 16.0;

/// The viewer of one frame.
pub struct Viewer<'a> {
    /// The graph file (texture paths are relative to it), once there is one.
    pub file: Option<&'a std::path::Path>,
    /// The document (read only).
    pub doc: &'a EditorDoc,
    /// Whether sliders span the hard range (Ctrl held).
    pub hard: bool,
    /// The actions queued this frame.
    pub actions: Vec<Action>,
    /// The canvas → screen transform snarl used this frame.
    pub to_screen: Option<egui::emath::TSTransform>,
    /// The shader generator's error (naga's, mapped to a node) and its node.
    pub shader_error: Option<(String, String)>,
    /// A transform to impose this frame (frame all), canvas → screen.
    pub set_transform: Option<egui::emath::TSTransform>,
    /// The swatches of the nodes whose preview is on, by node id.
    pub swatches: std::collections::BTreeMap<String, Swatch>,
    /// The overview's pins and wires, when this frame's zoom is under [`LOW_DETAIL_ZOOM`].
    pub overview: Overview,
    /// The canvas' rect on screen (the nodes away from it are culled).
    pub canvas: egui::Rect,
    /// This frame's culling ([`super::cull`]), made once the transform is known.
    pub culling: Culling,
    /// Where the whole canvas' nodes and wires are this frame (egui-snarl may be handed
    /// only some of them, [`super::handoff`]).
    pub places: Places,
    /// The nodes handed to egui-snarl this frame, by node id (`None`: all).
    pub handed: Option<Vec<bool>>,
    /// How egui-snarl last drew each node in the overview ([`super::stand_in`]).
    pub looks: &'a mut Looks,
    /// Where egui-snarl paints its wires this frame, to be sorted ([`super::wire_order`]).
    pub wires: Option<super::wire_order::Slot>,
    /// The frame of each node egui-snarl drew in full this frame (document index, canvas
    /// rect; [`OUTPUT_DRAWN`] for the Material Output node), in drawing order.
    pub drawn: Vec<(usize, egui::Rect)>,
    /// The selected nodes, outlined ([`super::selection`]).
    pub selection: &'a super::selection::Selection,
    /// The modifiers to give egui back once it has read them ([`super::select_ui`] hides
    /// Shift from it), with the context they belong to.
    pub restore: Option<(egui::Context, egui::Modifiers)>,
    /// The pin rows drawn this frame, for their tooltips ([`super::pin_tips`]).
    pub pin_rows: PinRows,
    /// The values refused on the canvas, shown under their inputs ([`super::entry`]).
    pub rejections: &'a Rejections,
    /// Where egui-snarl draws each pin this frame ([`super::wires`]).
    pub pins: super::wires::PinPlaces,
    /// The ramp-and-curve widgets drawn this frame: node id, the strip's or plot's rect
    /// (canvas points; [`super::ramp_ui`]).
    pub widgets: Vec<(String, egui::Rect)>,
    /// The collapsed nodes ([`super::collapse`]): their pins without a wire are not drawn.
    pub collapsed: &'a super::collapse::Collapsed,
}

/// The index [`Viewer::drawn`] gives the Material Output node (no document node).
pub const OUTPUT_DRAWN: usize = usize::MAX;

/// The outline of a selected node (Blender's orange).
pub const SELECTED_COLOR: Color32 = Color32::from_rgb(0xed, 0x57, 0x00);

/// The outline of the active node (the last selected; Blender's white).
pub const ACTIVE_COLOR: Color32 = Color32::from_rgb(0xff, 0xff, 0xff);

/// The canvas' nodes (egui-snarl id, document index, position) and wires (document
/// indices) at the start of a frame.
#[derive(Clone, Debug, Default)]
pub struct Places {
    /// Each node: its id on the canvas, its document index and its position.
    pub nodes: Vec<(NodeId, usize, egui::Pos2)>,
    /// Each wire, by document index.
    pub wires: Vec<Wire>,
}

impl Places {
    /// The places of `snarl`'s nodes (those whose id `doc` knows) and wires.
    pub fn of(snarl: &Snarl<NodeView>, doc: &EditorDoc) -> Places {
        let nodes = snarl
            .nodes_pos_ids()
            .filter_map(|(n, pos, view)| Some((n, doc.index(&view.id)?, pos)))
            .collect();
        let index = |n: NodeId| snarl.get_node(n).and_then(|v| doc.index(&v.id));
        let wires = snarl
            .wires()
            .filter_map(|(from, to)| {
                Some((index(from.node)?, from.output, index(to.node)?, to.input))
            })
            .collect();
        Places { nodes, wires }
    }
}

impl Viewer<'_> {
    /// The tooltip of input (else output) pin `k` of node `id` ([`tip`]; a Material
    /// Output pin's: the graph output it writes).
    fn pin_tip(&self, id: &str, input: bool, k: usize) -> Option<String> {
        if id == OUTPUT_NODE {
            let o = self.doc.doc().outputs.get(k)?;
            let ty = self.doc.graph().and_then(|g| {
                let o = g.outputs().iter().find(|g| g.name == o.name)?;
                Some(o.ty)
            });
            let ty = ty.map_or(String::new(), |t| format!(" ({t})"));
            return Some(format!("graph output '{}'{ty}", o.name));
        }
        let ports = self.doc.ports(id)?;
        let decl = match input {
            true => ports.inputs.get(k)?,
            false => ports.outputs.get(k)?,
        };
        Some(tip(decl, self.doc.port_type(id, decl.ty), input))
    }

    /// Node `id`'s preview swatch, when its preview is on.
    fn show_swatch(&self, id: &str, ui: &mut Ui) {
        let side = egui::vec2(NODE_SWATCH_POINTS, NODE_SWATCH_POINTS);
        match self.swatches.get(id) {
            Some(Swatch::Image(t)) => {
                ui.image((*t, side));
            }
            Some(Swatch::Message(m)) => {
                ui.add(
                    egui::Label::new(
                        egui::RichText::new(m).color(Color32::from_rgb(255, 120, 110)),
                    )
                    .wrap(),
                );
            }
            Some(Swatch::Pending) => {
                ui.allocate_ui(side, |ui| ui.weak("rendering…"));
            }
            None => {}
        }
    }

    /// Whether node `id` shows its image rows under its pins ([`super::textures_ui`]):
    /// a texture node of a file (or of none yet), zoomed in.
    fn image_rows(&self, id: &str) -> bool {
        !self.low_detail() && super::textures::shows_image_row(self.doc, id)
    }

    /// The loader's errors at node `id`, and the shader generator's when it names `id`.
    /// The type of node `id` when it has the ramp-and-curve widget ([`super::ramps`]).
    fn widget_type(&self, id: &str) -> Option<String> {
        let ty = &self.doc.node(id)?.node_type;
        super::ramps::pinned(ty).map(|_| ty.clone())
    }

    /// How many input pins node `id` shows when the widget edits the rest: its first
    /// inputs, and every input up to the last one holding a link (a linked stop keeps its
    /// wire).
    fn widget_pins(&self, id: &str) -> Option<usize> {
        let node = self.doc.node(id)?;
        let pinned = super::ramps::pinned(&node.node_type)?;
        let ports = self.doc.ports(id)?;
        let linked = ports
            .inputs
            .iter()
            .rposition(|p| {
                node.inputs
                    .get(p.name.as_ref())
                    .is_some_and(|v| super::model::link_of(v).is_some())
            })
            .map_or(0, |k| k + 1);
        Some(pinned.max(linked).min(ports.inputs.len()))
    }

    fn errors_of(&self, id: &str) -> Vec<String> {
        let mut errors = self.doc.node_errors(id);
        if let Some((node, message)) = &self.shader_error
            && node == id
        {
            errors.push(message.clone());
        }
        errors
    }

    fn id<'s>(&self, snarl: &'s Snarl<NodeView>, node: NodeId) -> &'s str {
        &snarl[node].id
    }

    /// The name of input pin `k` of node `id` (of the Material Output node: its `k`th
    /// graph output).
    fn input_name(&self, id: &str, k: usize) -> Option<String> {
        if id == OUTPUT_NODE {
            return Some(self.doc.doc().outputs.get(k)?.name.clone());
        }
        Some(self.doc.ports(id)?.inputs.get(k)?.name.clone().into_owned())
    }

    /// The name of output pin `k` of node `id`.
    fn output_name(&self, id: &str, k: usize) -> Option<String> {
        Some(
            self.doc
                .ports(id)?
                .outputs
                .get(k)?
                .name
                .clone()
                .into_owned(),
        )
    }

    /// Paints the document's frames (format version 2) behind the nodes: each a box
    /// around the estimated rects of the nodes it holds on the canvas, in its colour, its
    /// label above them (canvas coordinates; egui-snarl's layer transform applies).
    fn paint_frames(&self, viewport: &egui::Rect, style: &egui::Style, painter: &egui::Painter) {
        let frames = &self.doc.doc().frames;
        if frames.is_empty() {
            return;
        }
        let at: std::collections::HashMap<usize, egui::Pos2> =
            self.places.nodes.iter().map(|&(_, k, p)| (k, p)).collect();
        let font = egui::TextStyle::Body.resolve(style);
        for f in frames {
            let node = |k: usize| Some(self.estimate(k, *at.get(&k)?));
            let Some(rect) = super::frames::rect(self.doc, f, node) else {
                continue;
            };
            if !rect.intersects(*viewport) {
                continue;
            }
            let [r, g, b] = f.color.unwrap_or([0.35, 0.35, 0.35]);
            let byte = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
            let color = Color32::from_rgb(byte(r), byte(g), byte(b));
            painter.rect(
                rect,
                6.0,
                color.gamma_multiply(0.25),
                Stroke::new(1.0, color.gamma_multiply(0.6)),
                egui::StrokeKind::Inside,
            );
            if !f.label.is_empty() {
                painter.text(
                    rect.min + egui::vec2(8.0, 4.0),
                    egui::Align2::LEFT_TOP,
                    &f.label,
                    font.clone(),
                    Color32::from_gray(220),
                );
            }
        }
    }

    /// Whether the node with id `id` is culled this frame.
    fn culled(&self, id: &str) -> bool {
        self.doc
            .index(id)
            .is_some_and(|k| self.culling.is_culled(k))
    }

    /// The culling of a frame drawn with `to_screen`: each node's estimated rect against
    /// the canvas' viewport (nothing is culled before the canvas' rect is known).
    fn cull(&self, to_screen: egui::emath::TSTransform) -> Culling {
        if !self.canvas.is_positive() {
            return Culling::default();
        }
        let viewport = to_screen.inverse() * self.canvas;
        let nodes = self
            .places
            .nodes
            .iter()
            .map(|&(_, k, pos)| (k, self.estimate(k, pos)));
        let wires = self.places.wires.iter().copied();
        Culling::new(viewport, self.doc.doc().nodes.len(), nodes, wires)
    }

    /// Document node `k`'s estimated rect at `pos` ([`super::layout::node_size`]; a
    /// collapsed node's header only).
    fn estimate(&self, k: usize, pos: egui::Pos2) -> egui::Rect {
        let (w, mut h) = self.doc.node_sizes().get(k).copied().unwrap_or_default();
        let collapsed = self.doc.doc().nodes.get(k).is_some_and(|n| {
            self.collapsed
                .contains(&super::collapse::key(self.doc, &n.id))
        });
        if collapsed {
            h = h.min(HEADER_HEIGHT);
        }
        egui::Rect::from_min_size(pos, egui::vec2(w, h))
    }

    /// Which nodes egui-snarl is handed in a frame drawn with `to_screen` (by node id, see
    /// [`super::handoff`]): those `selected`, those within [`POINTER_REACH`] of `pointer`
    /// (screen), culled ones holding a wire to a node drawn, and the others in view, except
    /// in the overview those with a look recorded for their current look (their
    /// stand-ins are painted instead).
    pub fn hand_over(
        &self,
        to_screen: egui::emath::TSTransform,
        selected: &[NodeId],
        pointer: Option<egui::Pos2>,
    ) -> Vec<bool> {
        let culling = self.cull(to_screen);
        let overview = to_screen.scaling < LOW_DETAIL_ZOOM;
        let reach = POINTER_REACH / to_screen.scaling;
        let pointer = pointer.map(|p| to_screen.inverse() * p);
        let len = self
            .places
            .nodes
            .iter()
            .map(|(n, ..)| n.0 + 1)
            .max()
            .unwrap_or(0);
        let mut keep = vec![true; len];
        for &(n, k, pos) in &self.places.nodes {
            let rect = self.looks.frame_at(k, pos).unwrap_or(self.estimate(k, pos));
            let near = pointer.is_some_and(|p| rect.expand(reach).contains(p));
            let needed = match culling.is_culled(k) {
                // A culled node keeps the pins of its wires to nodes drawn.
                true => culling.inputs(k, usize::MAX) > 0 || culling.outputs(k, usize::MAX) > 0,
                false => !overview || !self.looks.has(k, &self.look_key(k)),
            };
            keep[n.0] = needed || near || selected.contains(&n);
        }
        keep
    }

    /// What document node `k`'s overview look depends on ([`LookKey`]).
    fn look_key(&self, k: usize) -> LookKey {
        let id = &self.doc.doc().nodes[k].id;
        let errors = !self.errors_of(id).is_empty();
        LookKey {
            size: self.doc.node_sizes().get(k).copied().unwrap_or_default(),
            title: overview_title(id, errors),
            fill: self.header_fill(id),
            stroke: frame_stroke(errors),
        }
    }

    /// The fill of node `id`'s header: its category's colour ([`GROUP_COLOR`] for a group
    /// instance, dark red for an unknown type), dimmed when the node is muted.
    fn header_fill(&self, id: &str) -> Color32 {
        if id == OUTPUT_NODE {
            return match self.doc.body() {
                Some(_) => GROUP_COLOR,
                None => OUTPUT_COLOR,
            };
        }
        if id == INPUT_NODE {
            return GROUP_COLOR;
        }
        let fill = match self.doc.ports(id).map(|p| &p.kind) {
            Some(Kind::Type(t)) => category_color(t.category()),
            Some(Kind::Group { .. }) => GROUP_COLOR,
            Some(Kind::Switch { .. }) => SWITCH_COLOR,
            _ => Color32::from_rgb(0x50, 0x20, 0x20),
        };
        match self.doc.node(id).is_some_and(|n| n.muted) {
            true => muted(fill),
            false => fill,
        }
    }

    /// The pins of node `id` as the overview paints them on the edges of `body`.
    fn pin_shapes(&self, id: &str, body: Body, side: f32) -> Vec<Shape> {
        let Some(ports) = self.doc.ports(id) else {
            return Vec::new();
        };
        let inputs = ports.inputs.iter().enumerate();
        let outputs = ports.outputs.iter().enumerate();
        (inputs.map(|(k, d)| (body.input(k), d.ty)))
            .chain(outputs.map(|(k, d)| (body.output(k), d.ty)))
            .map(|(at, ty)| {
                let (fill, shape) = self.pin_look(id, ty);
                pin_shape(shape, at, side, fill)
            })
            .collect()
    }

    /// How many of a node's `all` input or output pins egui-snarl draws this frame: none in
    /// the overview (it paints them, `show_body`), else those `culled` leaves.
    fn pins_shown(
        &self,
        node: &NodeView,
        all: usize,
        culled: fn(&Culling, usize, usize) -> usize,
    ) -> usize {
        if self.low_detail() {
            return 0;
        }
        self.doc
            .index(&node.id)
            .map_or(all, |k| culled(&self.culling, k, all))
    }

    /// `frame` as this frame draws it: [`plain`] in the overview.
    fn frame_for_zoom(&self, frame: egui::Frame) -> egui::Frame {
        match self.low_detail() {
            true => plain(frame),
            false => frame,
        }
    }

    /// Whether this frame's zoom is under [`LOW_DETAIL_ZOOM`].
    fn low_detail(&self) -> bool {
        self.to_screen.is_some_and(|t| t.scaling < LOW_DETAIL_ZOOM)
    }

    /// A pin's colour (its socket type's) and shape (square for a generic port).
    fn pin_look(&self, node: &str, port: PortType) -> (Color32, PinShape) {
        match (self.doc.port_type(node, port), port) {
            (Some(t), PortType::Fixed(_)) => (socket_color(t), PinShape::Circle),
            (Some(t), PortType::Generic) => (socket_color(t), PinShape::Square),
            (None, _) => (GENERIC_UNKNOWN, PinShape::Square),
        }
    }

    fn pin(&self, node: &str, port: PortType) -> PinInfo {
        let (fill, shape) = self.pin_look(node, port);
        PinInfo::default()
            .with_shape(shape)
            .with_fill(fill)
            .with_wire_color(fill)
    }

    /// Paints the stand-ins of the nodes in view that egui-snarl was not handed (filled
    /// with `window`, pins `pin` across) behind the nodes it drew, and records their bodies
    /// for the wires.
    fn paint_stand_ins(&mut self, window: Color32, pin: f32) {
        let Some(handed) = &self.handed else {
            return;
        };
        let mut shapes = Vec::new();
        let mut bodies = Vec::new();
        for &(n, k, pos) in &self.places.nodes {
            if handed.get(n.0).copied().unwrap_or(true) || self.culling.is_culled(k) {
                continue;
            }
            if let Some(body) = self.looks.paint(k, pos, window, &mut shapes) {
                shapes.extend(self.pin_shapes(&self.doc.doc().nodes[k].id, body, pin));
                bodies.push((n, body));
            }
        }
        self.overview.paint_stand_ins(shapes, bodies);
    }

    /// Paints the overview's wires once the canvas drew its nodes (see [`super::overview`]),
    /// each in the mean of its ends' colours as egui-snarl mixes them, at least a pixel
    /// wide. `style` is the egui style the canvas drew with.
    pub fn paint_overview(&mut self, snarl: &Snarl<NodeView>, style: &egui::Style) {
        let Some(scale) = self
            .to_screen
            .map(|t| t.scaling)
            .filter(|_| self.low_detail())
        else {
            return;
        };
        let pin = style.spacing.interact_size.y * 0.6;
        self.paint_stand_ins(style.visuals.window_fill, pin);
        let width = (pin * 0.1).max(1.0 / scale);
        let mut wires: Vec<_> = snarl
            .wires()
            .filter_map(|(from, to)| {
                let (a, b) = (&snarl.get_node(from.node)?.id, &snarl.get_node(to.node)?.id);
                let out = self.doc.ports(a)?.outputs.get(from.output)?.ty;
                let inp = self.doc.ports(b)?.inputs.get(to.input)?.ty;
                let (ca, cb) = (self.pin_look(a, out).0, self.pin_look(b, inp).0);
                let mix = |x: u8, y: u8| x.midpoint(y);
                let color = Color32::from_rgba_premultiplied(
                    mix(ca.r(), cb.r()),
                    mix(ca.g(), cb.g()),
                    mix(ca.b(), cb.b()),
                    mix(ca.a(), cb.a()),
                );
                Some((from, to, Stroke::new(width, color)))
            })
            .collect();
        // egui-snarl lists its wires in a random hash order ([`super::wire_order`]):
        // painted by pin, crossings blend alike in every run.
        wires.sort_unstable_by_key(|&(from, to, _)| (from, to));
        self.overview.paint_wires(wires, pin * 3.0, scale);
    }
}

/// The header colour of the Material Output node (Blender's output nodes' red).
pub const OUTPUT_COLOR: Color32 = Color32::from_rgb(0x8a, 0x2e, 0x2e);

/// The colour of the reason a typed value was refused, under its input.
pub const REFUSED_COLOR: Color32 = Color32::from_rgb(255, 110, 100);

/// The colour of a Material Output pin that reads nothing, and of its note.
pub const UNCONNECTED_COLOR: Color32 = Color32::from_rgb(230, 60, 50);

impl Viewer<'_> {
    /// The Material Output node's header: its title (a click shows its outputs in the side
    /// panel) and a ⚠ when an output reads nothing.
    fn show_output_header(&mut self, ui: &mut Ui) {
        let notes: Vec<String> = (0..self.doc.doc().outputs.len())
            .filter_map(|k| {
                let n = note(self.doc, k)?;
                Some(format!("{}: {n}", self.doc.doc().outputs[k].name))
            })
            .collect();
        let (title, focus) = match self.doc.body() {
            Some(_) => (GROUP_OUTPUT_TITLE, GROUP_PANEL),
            None => (OUTPUT_TITLE, OUTPUT_NODE),
        };
        ui.horizontal(|ui| {
            let label = ui.add(
                egui::Label::new(egui::RichText::new(title).strong().color(Color32::WHITE))
                    .sense(egui::Sense::click()),
            );
            if label.clicked() {
                self.actions.push(Action::Focus(focus.to_owned()));
            }
            if !notes.is_empty() {
                ui.label(egui::RichText::new("⚠").color(UNCONNECTED_COLOR))
                    .on_hover_text(notes.join("\n"));
            }
        });
    }

    /// The Group Input node's header: its title (a click shows the interface in the side
    /// panel) and a ⚠ with the interface's errors.
    fn show_input_header(&mut self, ui: &mut Ui) {
        let errors = self.errors_of(INPUT_NODE);
        ui.horizontal(|ui| {
            let label = ui.add(
                egui::Label::new(
                    egui::RichText::new(INPUT_TITLE)
                        .strong()
                        .color(Color32::WHITE),
                )
                .sense(egui::Sense::click()),
            );
            if label.clicked() {
                self.actions.push(Action::Focus(GROUP_PANEL.to_owned()));
            }
            if !errors.is_empty() {
                ui.label(egui::RichText::new("⚠").color(UNCONNECTED_COLOR))
                    .on_hover_text(errors.join("\n"));
            }
        });
    }

    /// Pin `k` of the Material Output node: the output's name, its note when it reads
    /// nothing (red), and a menu to rename, disconnect or remove it.
    fn show_output_pin(&mut self, node: NodeId, k: usize, ui: &mut Ui) -> PinInfo {
        let Some(o) = self.doc.doc().outputs.get(k) else {
            return PinInfo::default();
        };
        let name = o.name.clone();
        let note = note(self.doc, k);
        let ty = self
            .doc
            .graph()
            .and_then(|g| g.outputs().iter().find(|g| g.name == name))
            .map(|g| g.ty);
        let fill = match (&note, ty) {
            (Some(_), _) => UNCONNECTED_COLOR,
            (None, Some(t)) => socket_color(t),
            (None, None) => GENERIC_UNKNOWN,
        };
        let info = PinInfo::default()
            .with_shape(PinShape::Circle)
            .with_fill(fill)
            .with_wire_color(fill);
        if self.low_detail() {
            return info;
        }
        self.pin_rows.note(node, true, k, ui);
        ui.horizontal(|ui| {
            let text = egui::RichText::new(&name);
            let text = match note.is_some() {
                true => text.color(UNCONNECTED_COLOR),
                false => text,
            };
            let label = ui
                .add(egui::Label::new(text).sense(egui::Sense::click()))
                .on_hover_text(format!(
                    "{} output '{name}'{}; right-click to rename or remove",
                    match self.doc.body() {
                        Some(_) => "group",
                        None => "graph",
                    },
                    ty.map_or(String::new(), |t| format!(" ({t})"))
                ));
            if let Some(n) = &note {
                ui.label(egui::RichText::new(n).italics().color(UNCONNECTED_COLOR));
            }
            label.context_menu(|ui| self.output_pin_menu(ui, &name));
        });
        info
    }

    /// The menu of the Material Output node's pin `name`: rename, disconnect, remove.
    fn output_pin_menu(&mut self, ui: &mut Ui, name: &str) {
        let key = egui::Id::new("matgraph-output-rename").with(name);
        let mut text = ui.data_mut(|d| d.get_temp::<String>(key).unwrap_or(name.to_owned()));
        ui.horizontal(|ui| {
            let edit = ui.add(egui::TextEdit::singleline(&mut text).desired_width(110.0));
            let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if (ui.button("Rename").clicked() || enter) && text != name {
                self.actions.push(Action::RenameOutput {
                    old: name.to_owned(),
                    new: text.clone(),
                });
                ui.close();
            }
        });
        ui.data_mut(|d| d.insert_temp(key, text));
        if ui.button("Disconnect").clicked() {
            self.actions.push(Action::Disconnect {
                node: OUTPUT_NODE.to_owned(),
                input: name.to_owned(),
            });
            ui.close();
        }
        if ui.button(format!("Remove output '{name}'")).clicked() {
            self.actions.push(Action::RemoveOutput(name.to_owned()));
            ui.close();
        }
    }

    /// The menu of input `input` of node `id` (its label or value editor): "Expose as
    /// parameter" with an editable name for an unlinked float, vector or colour input;
    /// "Un-expose" for one an exposed parameter feeds.
    fn input_pin_menu(&mut self, ui: &mut Ui, id: &str, input: &str) {
        if self.doc.body().is_some() {
            // A graph's parameters are nodes of its top level, set by the app.
            ui.weak("Inside a group: wire this input from the Group Input node, and expose the instance's input at the graph's top.");
            return;
        }
        if let Some(name) = params::feeding(self.doc, id, input) {
            if ui
                .button(format!("Un-expose parameter '{name}'"))
                .on_hover_text("the inputs it feeds keep its value, as literals")
                .clicked()
            {
                self.actions.push(Action::Unexpose(name));
                ui.close();
            }
            return;
        }
        if let Err(why) = params::exposable(self.doc, id, input) {
            ui.weak(why);
            return;
        }
        let key = egui::Id::new("matgraph-expose").with(id).with(input);
        // The name typed so far, while the menu stays open (shown in the previous frame).
        let frame = ui.ctx().cumulative_frame_nr();
        let kept = ui
            .data_mut(|d| d.get_temp::<(String, u64, bool)>(key))
            .filter(|(_, shown, _)| shown + 1 >= frame);
        // Until the field has had the focus once (a menu's first frame only measures it).
        let opening = !kept.as_ref().is_some_and(|k| k.2);
        let mut text = match kept {
            Some((text, ..)) => text,
            None => params::unique_name(self.doc.doc(), input),
        };
        let mut focused = !opening;
        ui.horizontal(|ui| {
            let output = egui::TextEdit::singleline(&mut text)
                .hint_text("name")
                .desired_width(110.0)
                .show(ui);
            let edit = output.response;
            focused |= edit.has_focus();
            if opening && !edit.has_focus() {
                // The name is focused and selected as the menu opens, so typing replaces it
                // and Enter exposes (an egui menu closes on any click, even in its fields).
                edit.request_focus();
                let mut state = output.state;
                let all = egui::text::CCursorRange::two(
                    egui::text::CCursor::new(0),
                    egui::text::CCursor::new(text.chars().count()),
                );
                state.cursor.set_char_range(Some(all));
                state.store(ui.ctx(), edit.id);
            }
            let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if ui
                .button("Expose as parameter")
                .on_hover_text(
                    "a parameter node holding this value, linked here and listed in the graph's parameters",
                )
                .clicked()
                || enter
            {
                self.actions.push(Action::Expose {
                    node: id.to_owned(),
                    input: input.to_owned(),
                    name: Some(std::mem::take(&mut text)).filter(|t| !t.is_empty()),
                });
                ui.close();
            }
        });
        ui.data_mut(|d| d.insert_temp(key, (text, frame, focused)));
    }

    /// The Material Output node's menu: add a standard output or any name, remove one.
    fn output_node_menu(&mut self, ui: &mut Ui) {
        let outputs = &self.doc.doc().outputs;
        let taken = |n: &str| outputs.iter().any(|o| o.name == n);
        for s in STANDARD {
            if ui
                .add_enabled(!taken(s), egui::Button::new(format!("Add output '{s}'")))
                .clicked()
            {
                self.actions.push(Action::AddOutput(s.to_owned()));
                ui.close();
            }
        }
        let key = egui::Id::new("matgraph-output-add");
        let mut text = ui.data_mut(|d| d.get_temp::<String>(key).unwrap_or_default());
        ui.horizontal(|ui| {
            let edit = ui.add(
                egui::TextEdit::singleline(&mut text)
                    .hint_text("name")
                    .desired_width(110.0),
            );
            let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if (ui.button("add output…").clicked() || enter) && !text.is_empty() {
                self.actions
                    .push(Action::AddOutput(std::mem::take(&mut text)));
                ui.close();
            }
        });
        ui.data_mut(|d| d.insert_temp(key, text));
        let names: Vec<String> = outputs.iter().map(|o| o.name.clone()).collect();
        if !names.is_empty() {
            ui.separator();
        }
        for n in names {
            if ui.button(format!("Remove output '{n}'")).clicked() {
                self.actions.push(Action::RemoveOutput(n));
                ui.close();
            }
        }
        ui.separator();
        if ui.button("Show outputs").clicked() {
            self.actions.push(Action::Focus(OUTPUT_NODE.to_owned()));
            ui.close();
        }
    }
}

/// A node's header text in the overview: its id, and an error mark when it has errors.
fn overview_title(id: &str, errors: bool) -> String {
    match errors {
        true => format!("{id} ⚠"),
        false => id.to_owned(),
    }
}

/// Canvas points between a frame and the nodes it holds.
pub const FRAME_MARGIN: f32 = 16.0;

/// Canvas points above a frame's nodes for its label.
pub const FRAME_LABEL: f32 = 20.0;

/// The colour of the notes after a node's title (its group, `muted`).
const NOTE_COLOR: Color32 = Color32::from_rgb(0xd8, 0xd8, 0xc0);

/// The header colour of a group instance (Blender's group node teal).
pub const GROUP_COLOR: Color32 = Color32::from_rgb(0x3b, 0x59, 0x59);

/// The header of a `switch` node (a variant set's switch): Blender's converter purple.
pub const SWITCH_COLOR: Color32 = Color32::from_rgb(0x4a, 0x3b, 0x6b);

/// A muted node's header colour: `c` blended half-way to red, as Blender draws a muted
/// node's header (`UI_ThemeColorBlend(color_id, TH_REDALERT, 0.5f)` in node_draw, its
/// default theme's alert red #ff0000).
fn muted(c: Color32) -> Color32 {
    let half = |x: u8, y: u8| x.midpoint(y);
    Color32::from_rgb(half(c.r(), 0xff), half(c.g(), 0), half(c.b(), 0))
}

/// A node frame's outline: red for a node with errors.
fn frame_stroke(errors: bool) -> Stroke {
    match errors {
        true => Stroke::new(2.0, Color32::from_rgb(230, 60, 50)),
        false => Stroke::NONE,
    }
}

/// `frame` with the outline `stroke`, its inner margin narrowed by as much as the outline
/// is wider than `frame`'s: egui counts a frame's outline in its size, and a node that
/// turned red after an edit (an error) grew by 2 points.
fn outlined(frame: egui::Frame, stroke: Stroke) -> egui::Frame {
    let d = (stroke.width - frame.stroke.width).round() as i8;
    let m = frame.inner_margin;
    frame.stroke(stroke).inner_margin(egui::Margin {
        left: m.left.saturating_sub(d),
        right: m.right.saturating_sub(d),
        top: m.top.saturating_sub(d),
        bottom: m.bottom.saturating_sub(d),
    })
}

/// `frame` as the overview draws it: without shadow, outline or rounding.
fn plain(frame: egui::Frame) -> egui::Frame {
    frame
        .shadow(egui::Shadow::NONE)
        .stroke(Stroke::NONE)
        .corner_radius(0)
}

impl Viewer<'_> {
    /// Input pin `pin`'s row (its name, value editor, refusal) and pin.
    fn input_pin(&mut self, pin: &InPin, ui: &mut Ui, snarl: &mut Snarl<NodeView>) -> PinInfo {
        let id = self.id(snarl, pin.id.node).to_owned();
        if id == OUTPUT_NODE {
            return self.show_output_pin(pin.id.node, pin.id.input, ui);
        }
        let doc = self.doc;
        let Some(decl) = doc.ports(&id).and_then(|p| p.inputs.get(pin.id.input)) else {
            return PinInfo::default();
        };
        let ty = self.doc.port_type(&id, decl.ty);
        let info = self.pin(&id, decl.ty);
        if self.low_detail() || self.culled(&id) {
            return info;
        }
        self.pin_rows.note(pin.id.node, true, pin.id.input, ui);
        let rejected = self.rejections.get(&id, decl.name.as_ref());
        // Compact editors: the bundled graphs' positions leave ~200 points per column.
        ui.spacing_mut().slider_width = 40.0;
        ui.spacing_mut().interact_size.x = 44.0;
        // The row, and under it (in red) why the last value typed was refused.
        ui.vertical(|ui| {
            let row = ui.horizontal(|ui| {
                // The label is drawn as a plain one (its colour unchanged); a click-sensing
                // region over it opens the input's menu (expose as parameter, un-expose).
                let label = ui.label(decl.name.as_ref());
                let label = ui
                    .interact(label.rect, label.id.with("menu"), egui::Sense::click())
                    .on_hover_ui(|ui| {
                        ui.label(tip(decl, ty, true));
                    });
                label.context_menu(|ui| self.input_pin_menu(ui, &id, decl.name.as_ref()));
                // A switch's choices take links only (the loader refuses a literal there).
                if pin.remotes.is_empty() && !super::variants::is_switch(doc, &id) {
                    let written = doc.node(&id).and_then(|n| n.inputs.get(decl.name.as_ref()));
                    let ty = ty.unwrap_or(crate::types::SocketType::Float);
                    let generic = doc.generic(&id).unwrap_or(crate::types::SocketType::Float);
                    let default = decl.default_for(generic);
                    let lanes = current_lanes(decl, ty, written, &default);
                    let edited = value_editor_checked(ui, decl, ty, &lanes, self.hard, true);
                    if let Some(value) = edited.value {
                        self.actions.push(Action::SetInput {
                            node: id.clone(),
                            input: decl.name.clone().into_owned(),
                            value,
                        });
                    }
                    if let Some(why) = edited.rejected {
                        self.actions.push(Action::Reject {
                            node: id.clone(),
                            input: decl.name.clone().into_owned(),
                            why,
                        });
                    }
                    let r = edited.response;
                    // Not on an enum's combo box: its popup and a context menu on its response
                    // share one id (`response.id.with("popup")`), and the menu's close on a
                    // primary click shut the list as it opened (wrap, filter could not be
                    // chosen). An enum cannot be a parameter; the label keeps the menu.
                    if decl.choices.is_empty() {
                        r.context_menu(|ui| self.input_pin_menu(ui, &id, decl.name.as_ref()));
                    }
                }
            });
            if let Some(why) = rejected {
                // Wrapped to the row's width, so that the node keeps its size.
                let width = row.response.rect.width();
                ui.scope(|ui| {
                    ui.set_max_width(width);
                    let text = egui::RichText::new(why).small().color(REFUSED_COLOR);
                    ui.add(egui::Label::new(text).wrap());
                });
            }
        });
        info
    }

    /// Output pin `pin`'s row (its name) and pin.
    fn output_pin(&mut self, pin: &OutPin, ui: &mut Ui, snarl: &mut Snarl<NodeView>) -> PinInfo {
        let id = self.id(snarl, pin.id.node).to_owned();
        let doc = self.doc;
        let Some(decl) = doc.ports(&id).and_then(|p| p.outputs.get(pin.id.output)) else {
            return PinInfo::default();
        };
        if self.low_detail() || self.culled(&id) {
            return self.pin(&id, decl.ty);
        }
        let ty = self.doc.port_type(&id, decl.ty);
        self.pin_rows.note(pin.id.node, false, pin.id.output, ui);
        // The hover's text is made only when it shows (a 300-node canvas has ~900 pins).
        ui.label(decl.name.as_ref()).on_hover_ui(|ui| {
            ui.label(tip(decl, ty, false));
        });
        self.pin(&id, decl.ty)
    }

    /// `info`, drawn not at all when node `id` is collapsed and the pin holds no wire
    /// (Blender's collapsed nodes show their wired sockets only).
    fn unwired_hidden(&self, id: &str, unwired: bool, info: PinInfo) -> PinInfo {
        let key = super::collapse::key(self.doc, id);
        match unwired && self.collapsed.contains(&key) {
            true => info
                .with_fill(Color32::TRANSPARENT)
                .with_stroke(Stroke::NONE),
            false => info,
        }
    }
}

impl SnarlViewer<NodeView> for Viewer<'_> {
    fn title(&mut self, node: &NodeView) -> String {
        if node.id == OUTPUT_NODE {
            return match self.doc.body() {
                Some(_) => GROUP_OUTPUT_TITLE,
                None => OUTPUT_TITLE,
            }
            .to_owned();
        }
        if node.id == INPUT_NODE {
            return INPUT_TITLE.to_owned();
        }
        // The id alone keeps nodes narrow (the bundled graphs leave 200 units per column);
        // the type is in the hover, the header colour and the side panel.
        node.id.clone()
    }

    fn show_header(
        &mut self,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        let id = self.id(snarl, node).to_owned();
        if self.culled(&id) {
            return;
        }
        if id == OUTPUT_NODE {
            self.show_output_header(ui);
            return;
        }
        if id == INPUT_NODE {
            self.show_input_header(ui);
            return;
        }
        let errors = self.errors_of(&id);
        let title = self.title(&snarl[node]);
        if self.low_detail() {
            // Painted, not laid out as widgets: each widget registers with egui's context
            // (a lock and hash maps), and a 300-node graph framed whole spent 6 % of its
            // frame on the headers' labels (benches/editor.rs). The node is still selected
            // and dragged by its frame.
            let text = overview_title(&title, !errors.is_empty());
            let font = egui::TextStyle::Body.resolve(ui.style());
            let galley = ui.painter().layout_no_wrap(text, font, Color32::WHITE);
            let (_, rect) = ui.allocate_space(galley.size());
            ui.painter()
                .galley(rect.min, galley.clone(), Color32::WHITE);
            if let Some(k) = self.doc.index(&id) {
                self.looks.header(k, ui.min_rect(), rect.min, galley);
            }
            return;
        }
        let notes = match (self.doc.node(&id), self.doc.ports(&id)) {
            (Some(n), Some(p)) => super::layout::header_notes(n, p),
            _ => Vec::new(),
        };
        ui.horizontal(|ui| {
            let label = ui.add(
                egui::Label::new(egui::RichText::new(title).strong().color(Color32::WHITE))
                    .sense(egui::Sense::click()),
            );
            if label.clicked() {
                self.actions.push(Action::Focus(id.clone()));
            }
            for note in notes {
                ui.label(egui::RichText::new(note).italics().color(NOTE_COLOR));
            }
            if !errors.is_empty() {
                ui.label(egui::RichText::new("⚠").color(Color32::from_rgb(255, 90, 80)))
                    .on_hover_text(errors.join("\n"));
            }
            if self.doc.body().is_some() {
                // The swatches render the whole graph's nodes (a group's are not cut).
                return;
            }
            let on = self.swatches.contains_key(&id);
            let toggle = ui
                .selectable_label(on, egui::RichText::new("👁").color(Color32::WHITE))
                .on_hover_text("preview this node's output");
            if toggle.clicked() {
                self.actions.push(Action::TogglePreview(id.clone()));
            }
        });
    }

    fn has_footer(&mut self, node: &NodeView) -> bool {
        (self.swatches.contains_key(&node.id)
            || self.image_rows(&node.id)
            || self.widget_type(&node.id).is_some())
            && !self.culled(&node.id)
    }

    fn show_footer(
        &mut self,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        let id = self.id(snarl, node).to_owned();
        if let Some(ty) = self.widget_type(&id) {
            ui.vertical(|ui| {
                let (edit, rect) = super::ramp_ui::show(ui, self.doc, &id, &ty);
                self.widgets.push((id.clone(), rect));
                if let Some((values, key)) = edit {
                    self.actions.push(Action::SetInputs {
                        node: id.clone(),
                        values,
                        key,
                    });
                }
                self.show_swatch(&id, ui);
            });
        } else if self.image_rows(&id) {
            ui.vertical(|ui| {
                if let Some(a) = super::textures_ui::node_rows(ui, self.doc, self.file, &id) {
                    self.actions.push(Action::Texture(a));
                }
                self.show_swatch(&id, ui);
            });
        } else {
            self.show_swatch(&id, ui);
        }
    }

    fn header_frame(
        &mut self,
        default: egui::Frame,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        snarl: &Snarl<NodeView>,
    ) -> egui::Frame {
        self.frame_for_zoom(default)
            .fill(self.header_fill(&snarl[node].id))
    }

    fn node_frame(
        &mut self,
        default: egui::Frame,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        snarl: &Snarl<NodeView>,
    ) -> egui::Frame {
        // The overview's nodes have no shadow, outline or rounding: a pixel or less there,
        // their tessellation was a third of the frame of a 300-node graph framed whole
        // (benches/editor.rs).
        let default = self.frame_for_zoom(default);
        if snarl[node].id == OUTPUT_NODE {
            let notes = (0..self.doc.doc().outputs.len()).any(|k| note(self.doc, k).is_some());
            return outlined(default.stroke(Stroke::NONE), frame_stroke(notes));
        }
        match self.errors_of(&snarl[node].id).is_empty() {
            true => default,
            false => outlined(default, frame_stroke(true)),
        }
    }

    fn inputs(&mut self, node: &NodeView) -> usize {
        if node.id == OUTPUT_NODE {
            // The overview paints no pins on it (its wires are the loader's outputs).
            return match self.low_detail() {
                true => 0,
                false => self.doc.doc().outputs.len(),
            };
        }
        let all = self.doc.ports(&node.id).map_or(0, |p| p.inputs.len());
        let all = self.widget_pins(&node.id).unwrap_or(all);
        self.pins_shown(node, all, Culling::inputs)
    }

    fn outputs(&mut self, node: &NodeView) -> usize {
        let all = self.doc.ports(&node.id).map_or(0, |p| p.outputs.len());
        self.pins_shown(node, all, Culling::outputs)
    }

    #[allow(refining_impl_trait)]
    fn show_input(
        &mut self,
        pin: &InPin,
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) -> super::wires::RecordedPin {
        let info = self.input_pin(pin, ui, snarl);
        let info = self.unwired_hidden(&snarl[pin.id.node].id, pin.remotes.is_empty(), info);
        self.pins.wrap(pin.id.node, true, pin.id.input, info)
    }

    #[allow(refining_impl_trait)]
    fn show_output(
        &mut self,
        pin: &OutPin,
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) -> super::wires::RecordedPin {
        let info = self.output_pin(pin, ui, snarl);
        let info = self.unwired_hidden(&snarl[pin.id.node].id, pin.remotes.is_empty(), info);
        self.pins.wrap(pin.id.node, false, pin.id.output, info)
    }

    fn has_body(&mut self, _: &NodeView) -> bool {
        self.low_detail()
    }

    /// The overview's body: the node's estimated full-detail size, its pins painted on
    /// its edges ([`Body`]).
    fn show_body(
        &mut self,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        let id = self.id(snarl, node);
        let Some(k) = self.doc.index(id) else {
            return;
        };
        let Some(&(w, h)) = self.doc.node_sizes().get(k) else {
            return;
        };
        let size = egui::vec2((w - BODY_INSET).max(0.0), (h - HEADER_HEIGHT).max(0.0));
        let body = Body(ui.allocate_space(size).1);
        self.overview.record(node, body);
        if self.culled(id) {
            // Off screen: its wires need the body, not the pins.
            return;
        }
        self.looks.body(k, body.0);
        let side = ui.spacing().interact_size.y * 0.6;
        let shapes = self.pin_shapes(id, body, side);
        ui.painter().add(Shape::Vec(shapes));
    }

    /// The background pattern, then (in the overview) the slot of the wires, behind the
    /// nodes; last, where egui-snarl's own wires will go ([`super::wire_order`]).
    fn draw_background(
        &mut self,
        background: Option<&BackgroundPattern>,
        viewport: &egui::Rect,
        snarl_style: &SnarlStyle,
        style: &egui::Style,
        painter: &egui::Painter,
        _: &Snarl<NodeView>,
    ) {
        if let Some(background) = background {
            background.draw(viewport, snarl_style, style, painter);
        }
        self.paint_frames(viewport, style, painter);
        if self.low_detail() {
            self.overview.reserve(painter);
        }
        self.wires = Some(super::wire_order::Slot::before_wires(painter));
    }

    /// Imposes the frame-all transform, and culls the nodes away from the viewport (this
    /// is called before any node is drawn).
    fn current_transform(
        &mut self,
        to_global: &mut egui::emath::TSTransform,
        _: &mut Snarl<NodeView>,
    ) {
        if let Some((ctx, modifiers)) = self.restore.take() {
            super::select_ui::SelectTool::restore(&ctx, Some(modifiers));
        }
        if let Some(t) = self.set_transform.take() {
            *to_global = t;
        }
        self.to_screen = Some(*to_global);
        self.culling = self.cull(*to_global);
    }

    /// Outlines the node when it is selected, puts the tooltips over its pins
    /// ([`super::pin_tips`]) and records how the overview drew it (its stand-in's look,
    /// [`super::stand_in`]).
    fn final_node_rect(
        &mut self,
        node: NodeId,
        rect: egui::Rect,
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        let Some(info) = snarl.get_node_info(node) else {
            return;
        };
        let id = info.value.id.clone();
        if self.selection.contains(&id) {
            let color = match self.selection.active() == Some(id.as_str()) {
                true => ACTIVE_COLOR,
                false => SELECTED_COLOR,
            };
            let zoom = self.to_screen.map_or(1.0, |t| t.scaling);
            let width = 2.0f32.max(1.0 / zoom);
            ui.painter().rect_stroke(
                rect.expand(width),
                ui.visuals().window_corner_radius,
                Stroke::new(width, color),
                egui::StrokeKind::Inside,
            );
        }
        let pin = ui.spacing().interact_size.y * 0.6;
        let mut rows = std::mem::take(&mut self.pin_rows);
        rows.hover(node, rect, pin, ui, |input, k| self.pin_tip(&id, input, k));
        self.pin_rows = rows;
        if id == OUTPUT_NODE {
            self.drawn.push((OUTPUT_DRAWN, rect));
            return;
        }
        let Some(k) = self.doc.index(&id) else {
            return;
        };
        if self.culling.is_culled(k) {
            return;
        }
        self.drawn.push((k, rect));
        let passes = super::mute::passes(self.doc, &id);
        if !passes.is_empty() && !self.low_detail() {
            let zoom = self.to_screen.map_or(1.0, |t| t.scaling);
            let pins = self.pins.of(node);
            super::mute::paint_passthrough(
                ui.painter(),
                node,
                &passes,
                &pins,
                2.0f32.max(1.0 / zoom),
            );
        }
        if self.low_detail() {
            let key = self.look_key(k);
            self.looks.frame(k, info.pos, rect, key);
        }
    }

    fn has_on_hover_popup(&mut self, _: &NodeView) -> bool {
        true
    }

    fn show_on_hover_popup(
        &mut self,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        if snarl[node].id == OUTPUT_NODE {
            match self.doc.body() {
                Some(_) => {
                    ui.strong(GROUP_OUTPUT_TITLE);
                    ui.label("The group's outputs: wire a node output into a pin; click the title to edit the interface.");
                }
                None => {
                    ui.strong(OUTPUT_TITLE);
                    ui.label(
                        "The graph's outputs: wire a node output into a pin; right-click for more.",
                    );
                }
            }
            return;
        }
        if snarl[node].id == INPUT_NODE {
            ui.strong(INPUT_TITLE);
            ui.label("The group's inputs: wire a pin into a node input; click the title to edit the interface.");
            return;
        }
        match self.doc.ports(&snarl[node].id).map(|p| &p.kind) {
            Some(Kind::Type(t)) => {
                ui.strong(format!("{}  ({})", t.name(), t.category()));
                ui.label(t.summary());
            }
            Some(Kind::Group { reference, doc, .. }) => {
                ui.strong(format!("group  {reference}"));
                if !doc.is_empty() {
                    ui.label(doc);
                }
            }
            Some(Kind::Switch { variant, .. }) => {
                ui.strong(format!("switch  (variant set '{variant}')"));
                ui.label("Passes on the input of the set's chosen value; one input per choice.");
            }
            _ => {}
        }
    }

    fn connect(&mut self, from: &OutPin, to: &InPin, snarl: &mut Snarl<NodeView>) {
        let (src, dst) = (
            self.id(snarl, from.id.node).to_owned(),
            self.id(snarl, to.id.node).to_owned(),
        );
        let (Some(output), Some(input)) = (
            self.output_name(&src, from.id.output),
            self.input_name(&dst, to.id.input),
        ) else {
            return;
        };
        self.actions.push(Action::Connect {
            from: src,
            output,
            to: dst,
            input,
        });
    }

    fn disconnect(&mut self, _from: &OutPin, to: &InPin, snarl: &mut Snarl<NodeView>) {
        self.drop_inputs(to, snarl);
    }

    fn drop_inputs(&mut self, pin: &InPin, snarl: &mut Snarl<NodeView>) {
        let id = self.id(snarl, pin.id.node).to_owned();
        if let Some(input) = self.input_name(&id, pin.id.input) {
            self.actions.push(Action::Disconnect { node: id, input });
        }
    }

    fn drop_outputs(&mut self, pin: &OutPin, snarl: &mut Snarl<NodeView>) {
        for r in &pin.remotes {
            let id = self.id(snarl, r.node).to_owned();
            if let Some(input) = self.input_name(&id, r.input) {
                self.actions.push(Action::Disconnect { node: id, input });
            }
        }
    }

    fn has_graph_menu(&mut self, _: egui::Pos2, _: &mut Snarl<NodeView>) -> bool {
        true
    }

    fn show_graph_menu(&mut self, pos: egui::Pos2, ui: &mut Ui, _: &mut Snarl<NodeView>) {
        self.actions.push(Action::Search {
            pos: [pos.x, pos.y],
            wire: None,
        });
        ui.close();
    }

    fn has_dropped_wire_menu(&mut self, _: AnyPins, _: &mut Snarl<NodeView>) -> bool {
        true
    }

    fn show_dropped_wire_menu(
        &mut self,
        pos: egui::Pos2,
        ui: &mut Ui,
        pins: AnyPins,
        snarl: &mut Snarl<NodeView>,
    ) {
        let wire = match pins {
            AnyPins::Out(&[p, ..]) => {
                let id = self.id(snarl, p.node).to_owned();
                let doc = self.doc;
                (|| {
                    let decl = doc.ports(&id)?.outputs.get(p.output)?;
                    let ty = doc.port_type(&id, decl.ty)?;
                    Some((
                        id.clone(),
                        decl.name.clone().into_owned(),
                        WireFilter::InputAccepting(ty),
                    ))
                })()
            }
            AnyPins::In(&[p, ..]) => {
                let id = self.id(snarl, p.node).to_owned();
                let doc = self.doc;
                (|| {
                    let decl = doc.ports(&id)?.inputs.get(p.input)?;
                    let ty = doc.port_type(&id, decl.ty)?;
                    Some((
                        id.clone(),
                        decl.name.clone().into_owned(),
                        WireFilter::OutputFeeding(ty),
                    ))
                })()
            }
            _ => None,
        };
        self.actions.push(Action::Search {
            pos: [pos.x, pos.y],
            wire,
        });
        ui.close();
    }

    fn has_node_menu(&mut self, _: &NodeView) -> bool {
        true
    }

    fn show_node_menu(
        &mut self,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        let id = self.id(snarl, node).to_owned();
        if id == OUTPUT_NODE && self.doc.body().is_none() {
            self.output_node_menu(ui);
            return;
        }
        if id == OUTPUT_NODE || id == INPUT_NODE {
            if ui.button("Edit the group's interface").clicked() {
                self.actions.push(Action::Focus(GROUP_PANEL.to_owned()));
                ui.close();
            }
            return;
        }
        if self.doc.ports(&id).and_then(|p| p.group()).is_some() {
            if ui.button("Enter group  (Tab)").clicked() {
                self.actions.push(Action::EnterGroup(id.clone()));
                ui.close();
            }
            if ui.button("Ungroup  (Alt+G)").clicked() {
                self.actions.push(Action::Ungroup(id.clone()));
                ui.close();
            }
            ui.separator();
        }
        if ui
            .button("Group selected  (Ctrl+G)")
            .on_hover_text(
                "the selected nodes (this one if none) become a group and one node using it",
            )
            .clicked()
        {
            self.actions.push(Action::GroupSelected);
            ui.close();
        }
        super::node_commands::node_menu(ui, self.doc, &id, &mut self.actions);
        ui.separator();
        if ui.button("Duplicate").clicked() {
            self.actions.push(Action::Duplicate(vec![id.clone()]));
            ui.close();
        }
        if ui.button("Delete").clicked() {
            self.actions.push(Action::Remove(vec![id.clone()]));
            ui.close();
        }
        if ui.button("Toggle preview").clicked() {
            self.actions.push(Action::TogglePreview(id.clone()));
            ui.close();
        }
        if ui
            .button("Preview this output")
            .on_hover_text("show this node's output in the main preview (Ctrl+Shift+click); the file is unchanged")
            .clicked()
        {
            self.actions.push(Action::PreviewOutput(Some(id.clone())));
            ui.close();
        }
        // A graph's parameters are nodes of its top level (not inside a group).
        if params::is_parameter_node(self.doc, &id) && self.doc.body().is_none() {
            ui.separator();
            match params::of_node(self.doc.doc(), &id).map(|p| p.name.clone()) {
                Some(name) => {
                    if ui
                        .button(format!("Un-expose parameter '{name}'"))
                        .on_hover_text("the inputs it feeds keep its value, as literals")
                        .clicked()
                    {
                        self.actions.push(Action::Unexpose(name));
                        ui.close();
                    }
                }
                None => {
                    if ui.button("Expose as parameter").clicked() {
                        self.actions.push(Action::ListParameter(id.clone()));
                        ui.close();
                    }
                }
            }
            if ui.button("Edit parameters").clicked() {
                self.actions
                    .push(Action::Focus(params::PARAMETERS_PANEL.to_owned()));
                ui.close();
            }
        }
        if ui.button("Show docs").clicked() {
            self.actions.push(Action::Focus(id));
            ui.close();
        }
    }
}
