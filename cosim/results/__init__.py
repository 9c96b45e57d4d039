"""What comes out of a run: its record, the files written, the plots and the paper's claims."""
