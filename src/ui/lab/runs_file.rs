//! The table of runs as a file: Save CSV writes it beside the screenshots (the page
//! downloads it).

use super::model::Lab;

impl Lab {
    /// Saves the scene's table of runs as CSV, `particle-lab-SCENE-runs-MILLIS.csv` in
    /// the current directory (on the page, a download); the status line says where, or
    /// why not.
    pub fn save_runs(&mut self) {
        let Some(table) = self.scene.runs() else { return };
        let millis = web_time::SystemTime::now()
            .duration_since(web_time::UNIX_EPOCH)
            .map(|d| d.as_millis())
            .unwrap_or_default();
        let name = format!("particle-lab-{}-runs-{millis}.csv", self.entry.info().name);
        let csv = table.csv();
        self.status = save(&name, &csv);
    }
}

#[cfg(not(target_arch = "wasm32"))]
fn save(name: &str, csv: &str) -> String {
    let path = std::path::Path::new(name);
    match crate::writing::write_atomic(path, csv.as_bytes()) {
        Ok(()) => format!("table of runs saved as {}", crate::messages::path(path)),
        Err(e) => format!("cannot write {}: {e}", crate::messages::path(path)),
    }
}

#[cfg(target_arch = "wasm32")]
fn save(name: &str, csv: &str) -> String {
    match crate::ui::page::download(name, "text/csv", csv.as_bytes()) {
        Ok(()) => format!("table of runs downloaded as {name}"),
        Err(why) => format!("cannot download the table of runs: {why}"),
    }
}
