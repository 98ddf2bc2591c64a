//! Colours with opacity.

/// An sRGB colour with opacity `alpha` in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Color {
    /// Red channel, 0–255.
    pub r: u8,
    /// Green channel, 0–255.
    pub g: u8,
    /// Blue channel, 0–255.
    pub b: u8,
    /// Opacity, 0 (transparent) to 1 (opaque).
    pub alpha: f64,
}

impl Color {
    /// Opaque colour from its 0–255 channels.
    pub const fn rgb(r: u8, g: u8, b: u8) -> Self {
        Self {
            r,
            g,
            b,
            alpha: 1.0,
        }
    }
    /// The same colour with opacity `alpha` (clamped to [0, 1]).
    pub fn with_alpha(self, alpha: f64) -> Self {
        Self {
            alpha: if alpha.is_finite() {
                alpha.clamp(0.0, 1.0)
            } else {
                1.0
            },
            ..self
        }
    }
    /// `#rrggbb` text of the colour (opacity excluded).
    pub fn hex(&self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.r, self.g, self.b)
    }
    /// Black.
    pub const BLACK: Color = Color::rgb(0, 0, 0);
    /// White.
    pub const WHITE: Color = Color::rgb(255, 255, 255);
    /// Mid grey (experimental bands).
    pub const GREY: Color = Color::rgb(128, 128, 128);
    /// Light grey (grid lines).
    pub const LIGHT_GREY: Color = Color::rgb(220, 220, 220);
    /// Strong blue (predictions).
    pub const BLUE: Color = Color::rgb(0, 90, 181);
    /// Strong red.
    pub const RED: Color = Color::rgb(200, 30, 45);
    /// Orange.
    pub const ORANGE: Color = Color::rgb(230, 120, 0);
    /// Green.
    pub const GREEN: Color = Color::rgb(20, 140, 60);
}
